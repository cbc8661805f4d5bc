// The repeatability check (solver/repeatability.h) in the result JSON, the
// summary and the HTML report.
#pragma once

#include "odomcal/plugin/report/svg_plot.h"
#include "odomcal/solver/repeatability.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace odomcal {

// The result JSON's `repeatability` section (docs/result_schema.md); null
// when the command did not check.
nlohmann::json RepeatabilityToJson(
    const std::optional<Repeatability>& repeatability);

// One summary line: "  repeatability: halves agree (chi-square 4.1 on 6
// dof, p 0.66); quarters agree (...)", or why it did not run.
std::string RepeatabilitySummary(const Repeatability& repeatability);

// The blocks' estimates over time, a panel per parameter.
PlotFigure RepeatabilityPlot(const Repeatability& repeatability);

// The report's section: the summary line, a table of the blocks of each test
// and their plot.
std::string RepeatabilityHtml(const Repeatability& repeatability);

}  // namespace odomcal
