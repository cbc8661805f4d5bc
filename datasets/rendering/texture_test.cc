#include "odomcal/datasets/rendering/texture.h"

#include "odomcal/datasets/rendering/dataset_presets.h"
#include "odomcal/datasets/rendering/room_scene.h"
#include "odomcal/datasets/rendering/value_noise.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace odomcal {
namespace {

// Luminance of level 0 as a flat array.
std::vector<double> Luminance(const Texture& texture) {
  std::vector<double> out;
  for (int y = 0; y < texture.height(); ++y) {
    for (int x = 0; x < texture.width(); ++x) {
      out.push_back(texture.Texel(0, x, y).mean());
    }
  }
  return out;
}

// Normalised autocorrelation of a w x h image at shift (dx, dy) >= 0.
double Autocorrelation(
    const std::vector<double>& image, int w, int h, int dx, int dy) {
  double mean = 0.0;
  for (double v : image) mean += v;
  mean /= image.size();
  double var = 0.0;
  for (double v : image) var += (v - mean) * (v - mean);
  var /= image.size();
  double sum = 0.0;
  int n = 0;
  for (int y = 0; y + dy < h; ++y) {
    for (int x = 0; x + dx < w; ++x) {
      sum += (image[y * w + x] - mean) * (image[(y + dy) * w + x + dx] - mean);
      ++n;
    }
  }
  return sum / n / var;
}

TEST(Texture, MipLevelsAverageAndSampleAtTexelCentres) {
  std::vector<float> rgb;
  for (int i = 0; i < 5 * 3; ++i) {
    for (int c = 0; c < 3; ++c)
      rgb.push_back(static_cast<float>((i * 7 + c) % 11) / 10.0f);
  }
  const Texture texture(5, 3, rgb);
  ASSERT_EQ(texture.num_levels(), 4);  // 5x3, 3x2, 2x1, 1x1
  // Texel centre of level 0 is at +0.5: exact value there.
  EXPECT_NEAR(
      texture.Sample(2.5, 1.5, 0.0).x(), texture.Texel(0, 2, 1).x(), 1e-6);
  // Halfway between two texel centres: their mean.
  EXPECT_NEAR(texture.Sample(3.0, 1.5, 0.0).y(),
              0.5f * (texture.Texel(0, 2, 1).y() + texture.Texel(0, 3, 1).y()),
              1e-6);
  // Level 1 texel (0, 0) is the mean of the 2x2 block below it.
  const float block =
      0.25f * (texture.Texel(0, 0, 0).z() + texture.Texel(0, 1, 0).z() +
               texture.Texel(0, 0, 1).z() + texture.Texel(0, 1, 1).z());
  EXPECT_NEAR(texture.Texel(1, 0, 0).z(), block, 1e-6);
  EXPECT_THROW(Texture(0, 3, {}), std::invalid_argument);
}

TEST(ValueNoise, DeterministicForASeedAndDifferentAcrossSeeds) {
  ValueNoiseOptions options;
  options.width = 64;
  options.height = 48;
  options.seed = 7;
  const Texture a = MakeValueNoiseTexture(options);
  const Texture b = MakeValueNoiseTexture(options);
  options.seed = 8;
  const Texture c = MakeValueNoiseTexture(options);
  EXPECT_EQ(Luminance(a), Luminance(b));
  EXPECT_NE(Luminance(a), Luminance(c));
}

// A tiled or periodic texture shows an autocorrelation peak at its period;
// value noise decorrelates beyond its coarsest octave (256 texels) and only
// the coarse octaves correlate at mid-range shifts.
TEST(ValueNoise, NotRepetitive) {
  ValueNoiseOptions options;
  options.width = 640;
  options.height = 640;
  options.seed = 3;
  const Texture texture = MakeValueNoiseTexture(options);
  const std::vector<double> lum = Luminance(texture);
  double max_mid = 0.0, max_far = 0.0;
  for (int shift = 64; shift < 384; shift += 3) {
    const double c =
        std::max(std::abs(Autocorrelation(lum, 640, 640, shift, 0)),
                 std::abs(Autocorrelation(lum, 640, 640, 0, shift)));
    double& max = shift < 256 ? max_mid : max_far;
    max = std::max(max, c);
  }
  EXPECT_LT(max_mid, 0.35);
  EXPECT_LT(max_far, 0.15);
  EXPECT_GT(Autocorrelation(lum, 640, 640, 1, 0), 0.5);  // smooth at one texel
}

// Band-pass energy (level k minus level k+1, both from the mip pyramid) must
// be substantial at every octave from 2 to 128 texels, and the overall
// contrast high.
TEST(ValueNoise, MultiScaleHighContrast) {
  ValueNoiseOptions options;
  options.width = 512;
  options.height = 512;
  options.seed = 11;
  const Texture texture = MakeValueNoiseTexture(options);
  const std::vector<double> lum = Luminance(texture);
  double mean = 0.0, var = 0.0;
  for (double v : lum) mean += v / lum.size();
  for (double v : lum) var += (v - mean) * (v - mean) / lum.size();
  EXPECT_GT(std::sqrt(var), 0.12);
  for (int level = 0; level <= 6; ++level) {
    const int w = (texture.width() + (1 << level) - 1) >> level;
    const int h = (texture.height() + (1 << level) - 1) >> level;
    double band = 0.0;
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const double fine = texture.Texel(level, x, y).mean();
        const double coarse = texture.Texel(level + 1, x / 2, y / 2).mean();
        band += (fine - coarse) * (fine - coarse);
      }
    }
    SCOPED_TRACE("level " + std::to_string(level));
    EXPECT_GT(std::sqrt(band / (w * h)), 0.02);
  }
}

// --texture repetitive: every textured surface shows the same tile, repeated
// with its period; the default gives each surface its own noise.
TEST(RoomScene, RepeatedTileOnEverySurface) {
  RoomSceneOptions options;
  options.seed = 5;
  options.repeat_period_texels = 32;
  const RoomScene scene =
      BuildRoomScene(MakeDatasetPreset("small", 1).layout, options);
  std::vector<const Texture*> textured;
  for (const Texture& texture : scene.textures) {
    if (texture.width() > 80 && texture.height() > 80) {
      textured.push_back(&texture);
    }
  }
  ASSERT_GE(textured.size(), 2u);
  for (const Texture* texture : textured) {
    EXPECT_EQ(texture->Texel(0, 3, 7), texture->Texel(0, 3 + 32, 7 + 64));
    EXPECT_EQ(texture->Texel(0, 3, 7), textured[0]->Texel(0, 3, 7));
  }
  EXPECT_NE(textured[0]->Texel(0, 3, 7), textured[0]->Texel(0, 4, 7));

  options.repeat_period_texels = 0;
  const RoomScene own =
      BuildRoomScene(MakeDatasetPreset("small", 1).layout, options);
  ASSERT_GE(own.textures.size(), 2u);
  EXPECT_NE(own.textures[0].Texel(0, 3, 7), own.textures[1].Texel(0, 3, 7));

  options.repeat_period_texels = 24;  // not a power of two
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options.repeat_period_texels = 1;  // below min_period_texels
  EXPECT_THROW(options.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace odomcal
