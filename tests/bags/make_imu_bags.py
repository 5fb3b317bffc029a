#!/usr/bin/python3
"""Writes the same simulated six-axis IMU as every bag format gyrocomp reads, plus its CSV.

    make_imu_bags.py OUT_DIR [--seconds S] [--rate HZ] [--seed N] [--camera-bytes B]
                             [--formats ros1,ros1-bz2,ros1-lz4,mcap,mcap-zstd,mcap-lz4,db3]
    make_imu_bags.py --dump-ros1 BAG TOPIC OUT.csv     (read a ROS 1 bag back with Python rosbag)

Files in OUT_DIR:
    imu.csv                 time_s (header stamp), x_rad_s, y_rad_s, z_rad_s, x_m_s2, y_m_s2, z_m_s2,
                            temp_c (nearest 1 Hz temperature), receive_time_s; every value with
                            17 significant digits (exact doubles)
    imu.bag, imu_bz2.bag, imu_lz4.bag   ROS 1 bags written by Debian's python3-rosbag (rosbag.Bag)
    imu.mcap, imu_zstd.mcap, imu_lz4.mcap   MCAP written here from the MCAP specification
    imu_db3/                rosbag2 sqlite3 folder (metadata.yaml + imu_db3_0.db3)
Topics: /imu0 (sensor_msgs/Imu at --rate), /imu0/temperature (sensor_msgs/Temperature at 1 Hz),
and, with --camera-bytes B > 0, /cam0/image_raw (sensor_msgs/Image, one B-byte image per 10 IMU
messages) so that a reader that keeps everything shows it in its memory.
Header stamps are t0 + i / rate exactly in integer nanoseconds; the receive time is 2 ms later.
The MCAP and CDR writers here are written from the specifications (mcap.dev/spec; OMG CDR), not
from gyrocomp's reader, so the two check each other.
"""
import argparse
import os
import sqlite3
import struct
import subprocess
import sys
import zlib

import numpy as np

T0_NS = 1_700_000_000 * 1_000_000_000
LATENCY_NS = 2_000_000


def simulate(seconds, rate, seed):
    """White noise + bias random walk per axis (gyro rad/s, accel m/s^2), gravity on z."""
    n = int(round(seconds * rate))
    rng = np.random.default_rng(seed)
    dt = 1.0 / rate
    gyro_n, gyro_k = 1.7e-4, 2.0e-6     # rad/s/sqrt(Hz), rad/s^2/sqrt(Hz)
    acc_n, acc_k = 2.0e-3, 3.0e-5       # m/s^2/sqrt(Hz), m/s^3/sqrt(Hz)
    def axis(nd, k, offset):
        white = rng.standard_normal(n) * nd / np.sqrt(dt)
        walk = np.cumsum(rng.standard_normal(n) * k * np.sqrt(dt))
        return offset + white + walk
    gyro = np.stack([axis(gyro_n, gyro_k, b) for b in (0.001, -0.002, 0.0005)], axis=1)
    acc = np.stack([axis(acc_n, acc_k, b) for b in (0.05, -0.03, 9.81)], axis=1)
    stamp_ns = T0_NS + (np.arange(n, dtype=np.int64) * 1_000_000_000) // int(rate)
    temp_stamp_ns = T0_NS + np.arange(int(seconds) + 1, dtype=np.int64) * 1_000_000_000
    temp_stamp_ns = temp_stamp_ns[temp_stamp_ns <= stamp_ns[-1]]  # the ones written (see messages())
    temp_c = 25.0 + 0.01 * np.arange(len(temp_stamp_ns))
    return stamp_ns, gyro, acc, temp_stamp_ns, temp_c


# ---- CDR (OMG CORBA 3.3 part 2, 9.3; XTypes 1.3 7.4.3.5 encapsulation 0x0001 = CDR_LE) ----
class Cdr:
    def __init__(self):
        self.b = bytearray(b"\x00\x01\x00\x00")

    def align(self, s):
        while (len(self.b) - 4) % s:
            self.b.append(0)

    def put(self, fmt, v, s):
        self.align(s)
        self.b += struct.pack("<" + fmt, v)

    def string(self, s):
        data = s.encode() + b"\x00"
        self.put("I", len(data), 4)
        self.b += data

    def header(self, ns, frame):
        self.put("i", ns // 1_000_000_000, 4)
        self.put("I", ns % 1_000_000_000, 4)
        self.string(frame)


def cdr_imu(ns, g, a, frame="imu0"):
    c = Cdr()
    c.header(ns, frame)
    for v in (0.0, 0.0, 0.0, 1.0) + (0.0,) * 9 + tuple(g) + (0.0,) * 9 + tuple(a) + (0.0,) * 9:
        c.put("d", float(v), 8)
    return bytes(c.b)


def cdr_temperature(ns, t, frame="imu0"):
    c = Cdr()
    c.header(ns, frame)
    c.put("d", float(t), 8)
    c.put("d", 0.0, 8)
    return bytes(c.b)


def cdr_image(ns, nbytes, frame="cam0"):
    c = Cdr()
    c.header(ns, frame)
    c.put("I", 1, 4)            # height
    c.put("I", nbytes, 4)       # width
    c.string("mono8")           # encoding
    c.put("B", 0, 1)            # is_bigendian
    c.put("I", nbytes, 4)       # step
    c.put("I", nbytes, 4)       # data: sequence<uint8>
    c.b += bytes(nbytes)
    return bytes(c.b)


def messages(sim, camera_bytes):
    """(topic, receive_ns, cdr bytes) in receive-time order (a generator: bags of hours stream)."""
    stamp_ns, gyro, acc, temp_ns, temp_c = sim
    ti = 0
    for i in range(len(stamp_ns)):
        ns = int(stamp_ns[i])
        while ti < len(temp_ns) and int(temp_ns[ti]) <= ns:
            yield ("/imu0/temperature", int(temp_ns[ti]) + LATENCY_NS, cdr_temperature(int(temp_ns[ti]), temp_c[ti]))
            ti += 1
        yield ("/imu0", ns + LATENCY_NS, cdr_imu(ns, gyro[i], acc[i]))
        if camera_bytes and i % 10 == 0:
            yield ("/cam0/image_raw", ns + LATENCY_NS + 1, cdr_image(ns, camera_bytes))


TYPES = {"/imu0": "sensor_msgs/msg/Imu", "/imu0/temperature": "sensor_msgs/msg/Temperature",
         "/cam0/image_raw": "sensor_msgs/msg/Image"}


# ---- MCAP (mcap.dev/spec: Magic, Records, Header 0x01, Footer 0x02, Schema 0x03, Channel 0x04,
# ---- Message 0x05, Chunk 0x06, Data End 0x0F) ----
MAGIC = b"\x89MCAP0\r\n"


def record(op, content):
    return struct.pack("<BQ", op, len(content)) + content


def mstr(s):
    b = s.encode()
    return struct.pack("<I", len(b)) + b


def compress(method, data):
    if method == "":
        return data
    cmd = {"zstd": ["zstd", "-q", "-c"], "lz4": ["lz4", "-q", "-c"]}[method]
    return subprocess.run(cmd, input=data, stdout=subprocess.PIPE, check=True).stdout


def write_mcap(path, msgs, compression, chunk_bytes=768 * 1024):
    ids = {t: i + 1 for i, t in enumerate(TYPES)}
    with open(path, "wb") as f:
        crc = 0  # "Data End" data_section_crc: CRC-32 of every byte before it, leading magic included

        def put(b):
            nonlocal crc
            f.write(b)
            crc = zlib.crc32(b, crc)

        put(MAGIC)
        put(record(0x01, mstr("ros2") + mstr("gyrocomp make_imu_bags.py")))
        pending = bytearray()
        start = end = None
        announced = set()

        def flush():
            nonlocal pending, start, end
            if not pending:
                return
            data = bytes(pending)
            comp = compress(compression, data)
            content = (struct.pack("<QQQI", start, end, len(data), zlib.crc32(data)) + mstr(compression) +
                       struct.pack("<Q", len(comp)) + comp)
            put(record(0x06, content))
            pending = bytearray()
            start = end = None

        seq = 0
        for topic, t, data in msgs:
            if topic not in announced:   # Schema + Channel in the chunk that first uses them
                announced.add(topic)
                i = ids[topic]
                pending += record(0x03, struct.pack("<H", i) + mstr(TYPES[topic]) + mstr("ros2msg") + struct.pack("<I", 0))
                pending += record(0x04, struct.pack("<HH", i, i) + mstr(topic) + mstr("cdr") + struct.pack("<I", 0))
            pending += record(0x05, struct.pack("<HIQQ", ids[topic], seq, t, t) + data)
            seq += 1
            start = t if start is None else min(start, t)
            end = t if end is None else max(end, t)
            if len(pending) >= chunk_bytes:
                flush()
        flush()
        f.write(record(0x0F, struct.pack("<I", crc)))
        f.write(record(0x02, struct.pack("<QQI", 0, 0, 0)))
        f.write(MAGIC)


# ---- rosbag2 sqlite3 (rosbag2_storage_sqlite3 sqlite_storage.cpp schema) ----
def write_db3(folder, msgs):
    os.makedirs(folder, exist_ok=True)
    name = os.path.basename(folder) + "_0.db3"
    db = sqlite3.connect(os.path.join(folder, name))
    db.execute("CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, "
               "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL)")
    db.execute("CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, "
               "timestamp INTEGER NOT NULL, data BLOB NOT NULL)")
    ids = {t: i + 1 for i, t in enumerate(TYPES)}
    for t, i in ids.items():
        db.execute("INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')", (i, t, TYPES[t]))
    db.executemany("INSERT INTO messages(topic_id, timestamp, data) VALUES (?, ?, ?)",
                   ((ids[t], ns, d) for t, ns, d in msgs))
    db.commit()
    db.close()
    with open(os.path.join(folder, "metadata.yaml"), "w") as f:
        f.write("rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: sqlite3\n"
                "  relative_file_paths:\n    - %s\n  message_count: %d\n" % (name, len(msgs)))


# ---- ROS 1 through Debian's python3-rosbag ----
def write_ros1(path, sim, compression, camera_bytes):
    import rosbag
    import rospy
    from sensor_msgs.msg import Image, Imu, Temperature
    stamp_ns, gyro, acc, temp_ns, temp_c = sim
    with rosbag.Bag(path, "w", compression=compression) as bag:
        ti = 0
        for i in range(len(stamp_ns)):
            ns = int(stamp_ns[i])
            while ti < len(temp_ns) and int(temp_ns[ti]) <= ns:
                m = Temperature()
                m.header.stamp = rospy.Time(nsecs=int(temp_ns[ti]))
                m.header.frame_id = "imu0"
                m.temperature = float(temp_c[ti])
                bag.write("/imu0/temperature", m, rospy.Time(nsecs=int(temp_ns[ti]) + LATENCY_NS))
                ti += 1
            m = Imu()
            m.header.stamp = rospy.Time(nsecs=ns)
            m.header.frame_id = "imu0"
            m.orientation.w = 1.0
            m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z = (float(v) for v in gyro[i])
            m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z = (float(v) for v in acc[i])
            bag.write("/imu0", m, rospy.Time(nsecs=ns + LATENCY_NS))
            if camera_bytes and i % 10 == 0:
                img = Image()
                img.header.stamp = rospy.Time(nsecs=ns)
                img.height, img.width, img.step, img.encoding = 1, camera_bytes, camera_bytes, "mono8"
                img.data = bytes(camera_bytes)
                bag.write("/cam0/image_raw", img, rospy.Time(nsecs=ns + LATENCY_NS + 1))


def g17(v):
    return "%.17g" % v


def write_csv(path, sim):
    stamp_ns, gyro, acc, temp_ns, temp_c = sim
    # Nearest temperature by header stamp (ties to the earlier one).
    idx = np.searchsorted(temp_ns, stamp_ns)
    with open(path, "w") as f:
        f.write("time_s,x_rad_s,y_rad_s,z_rad_s,x_m_s2,y_m_s2,z_m_s2,temp_c,receive_time_s\n")
        for i in range(len(stamp_ns)):
            ns = int(stamp_ns[i])
            j = int(idx[i])
            if j == len(temp_ns) or (j > 0 and ns - int(temp_ns[j - 1]) <= int(temp_ns[j]) - ns):
                j = max(j - 1, 0)
            r = ns + LATENCY_NS
            t = ns // 1_000_000_000 + (ns % 1_000_000_000) / 1e9
            tr = r // 1_000_000_000 + (r % 1_000_000_000) / 1e9
            f.write(",".join([g17(t)] + [g17(v) for v in gyro[i]] + [g17(v) for v in acc[i]] +
                             [g17(temp_c[j]), g17(tr)]) + "\n")


def dump_ros1(bag_path, topic, out):
    """The independent reference extract: Python rosbag's own reading of the bag."""
    import rosbag
    with rosbag.Bag(bag_path) as bag, open(out, "w") as f:
        f.write("time_s,x_rad_s,y_rad_s,z_rad_s,x_m_s2,y_m_s2,z_m_s2,receive_time_s\n")
        for _, m, t in bag.read_messages(topics=[topic]):
            s = m.header.stamp
            w, a = m.angular_velocity, m.linear_acceleration
            f.write(",".join(g17(v) for v in (s.secs + s.nsecs / 1e9, w.x, w.y, w.z, a.x, a.y, a.z,
                                               t.secs + t.nsecs / 1e9)) + "\n")


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--dump-ros1":
        dump_ros1(*sys.argv[2:5])
        return
    p = argparse.ArgumentParser()
    p.add_argument("out_dir")
    p.add_argument("--seconds", type=float, default=60.0)
    p.add_argument("--rate", type=float, default=200.0)
    p.add_argument("--seed", type=int, default=25)
    p.add_argument("--camera-bytes", type=int, default=0)
    p.add_argument("--formats", default="ros1,ros1-bz2,ros1-lz4,mcap,mcap-zstd,mcap-lz4,db3,csv")
    a = p.parse_args()
    os.makedirs(a.out_dir, exist_ok=True)
    sim = simulate(a.seconds, a.rate, a.seed)
    formats = a.formats.split(",")
    if "csv" in formats:
        write_csv(os.path.join(a.out_dir, "imu.csv"), sim)
    for f, comp, name in (("mcap", "", "imu.mcap"), ("mcap-zstd", "zstd", "imu_zstd.mcap"),
                          ("mcap-lz4", "lz4", "imu_lz4.mcap")):
        if f in formats:
            write_mcap(os.path.join(a.out_dir, name), messages(sim, a.camera_bytes), comp)
    if "db3" in formats:
        write_db3(os.path.join(a.out_dir, "imu_db3"), list(messages(sim, a.camera_bytes)))
    for f, comp, name in (("ros1", "none", "imu.bag"), ("ros1-bz2", "bz2", "imu_bz2.bag"),
                          ("ros1-lz4", "lz4", "imu_lz4.bag")):
        if f in formats:
            write_ros1(os.path.join(a.out_dir, name), sim, comp, a.camera_bytes)


if __name__ == "__main__":
    main()
