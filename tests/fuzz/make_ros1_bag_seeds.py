#!/usr/bin/python3
"""Writes the seed corpus of the ros1_bag and ros_message fuzz targets.

Needs Debian's python3-rosbag (hence /usr/bin/python3). Writes
corpus/ros1_bag/seed-*.bag (tiny bags: uncompressed, bz2, lz4, unindexed,
truncated) and corpus/ros_message/seed-* (first byte: decoder in the low
nibble, 0x10 for CDR; see ros_message_fuzzer.cc), each a few KB.
Usage: /usr/bin/python3 tests/fuzz/make_ros1_bag_seeds.py
"""
import io
import os
import struct

import rosbag
import rospy
from nav_msgs.msg import Odometry
from sensor_msgs.msg import CameraInfo, CompressedImage, Image, JointState

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")


def put(target, name, data):
    folder = os.path.join(ROOT, target)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "seed-" + name), "wb") as f:
        f.write(data)


def joint_state(i):
    m = JointState()
    m.header.stamp = rospy.Time(1700000000, i * 1000)
    m.name = ["left_wheel_joint", "right_wheel_joint"]
    m.position = [0.1 * i, 0.2 * i]
    m.velocity = [1.0, 2.0]
    return m


def compressed_image(i):
    m = CompressedImage()
    m.header.stamp = rospy.Time(1700000000, i * 1000 + 1)
    m.format = "png"
    m.data = b"\x89PNG\r\n\x1a\n"
    return m


def write_bag(path, compression, close=True):
    bag = rosbag.Bag(path, "w", compression=compression, chunk_threshold=200)
    for i in range(4):
        t = rospy.Time(1700000000, i * 1000 + 500)
        bag.write("/joint_states", joint_state(i), t)
        bag.write("/image/compressed", compressed_image(i), t)
    if close:
        bag.close()
    else:  # a killed recorder: no index
        bag._file.flush()


def bag_seeds(scratch):
    for name, compression in [("none", "none"), ("bz2", "bz2"), ("lz4", "lz4")]:
        path = os.path.join(scratch, name + ".bag")
        write_bag(path, compression)
        with open(path, "rb") as f:
            data = f.read()
        put("ros1_bag", name + ".bag", data)
        if name == "none":
            put("ros1_bag", "truncated.bag", data[:len(data) * 3 // 4])
    path = os.path.join(scratch, "unindexed.bag")
    write_bag(path, "none", close=False)
    with open(path, "rb") as f:
        put("ros1_bag", "unindexed.bag", f.read())


class Cdr:
    """Little-endian CDR with alignment from the byte after the header."""

    def __init__(self):
        self.out = bytearray(b"\x00\x01\x00\x00")

    def align(self, n):
        while (len(self.out) - 4) % n:
            self.out.append(0)

    def u32(self, v):
        self.align(4)
        self.out += struct.pack("<I", v)

    def f64(self, v):
        self.align(8)
        self.out += struct.pack("<d", v)

    def string(self, s):
        self.u32(len(s) + 1)
        self.out += s.encode() + b"\x00"

    def header(self, frame):
        self.u32(1700000000)
        self.u32(5)
        self.string(frame)


def ros1_bytes(message):
    buffer = io.BytesIO()
    message.serialize(buffer)
    return buffer.getvalue()


def message_seeds():
    image = Image()
    image.height, image.width, image.encoding, image.step = 1, 2, "mono8", 2
    image.data = b"\x01\x02"
    info = CameraInfo()
    info.distortion_model = "plumb_bob"
    info.D = [0.1, 0.0, 0.0, 0.0, 0.0]
    odom = Odometry()
    odom.pose.pose.orientation.w = 1.0
    for selector, message in enumerate([image, compressed_image(0), info, odom, joint_state(1)]):
        put("ros_message", "ros1_%d" % selector, bytes([selector]) + ros1_bytes(message))

    c = Cdr()
    c.header("odom")
    c.string("base_link")
    for v in [1.0, 2.0, 0.0, 0.0, 0.0, 0.0, 1.0] + [0.0] * 36 + [0.0] * 42:
        c.f64(v)
    put("ros_message", "cdr_odometry", bytes([0x13]) + bytes(c.out))
    c = Cdr()
    c.header("")
    c.u32(2)
    c.string("left")
    c.string("right")
    c.u32(0)  # empty position: no padding
    c.u32(2)
    c.f64(1.0)
    c.f64(2.0)
    c.u32(0)
    put("ros_message", "cdr_joint_state", bytes([0x14]) + bytes(c.out))
    c = Cdr()
    c.header("cam")
    c.u32(480)
    c.u32(640)
    c.string("plumb_bob")
    c.u32(1)
    c.f64(0.5)
    for v in range(30):
        c.f64(float(v))
    for v in [1, 1, 0, 0, 0, 0]:
        c.u32(v)
    c.out.append(0)
    put("ros_message", "cdr_camera_info", bytes([0x12]) + bytes(c.out))


def main():
    import tempfile
    with tempfile.TemporaryDirectory() as scratch:
        bag_seeds(scratch)
    message_seeds()


if __name__ == "__main__":
    main()
