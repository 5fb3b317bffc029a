// ROS 1 and ROS 2 (CDR) decoding of sensor_msgs/Imu and sensor_msgs/Temperature
// (include/gyrocomp/io/cdr.h, where the rules are cited).
#include "gyrocomp/io/cdr.h"

#include <bit>
#include <cstring>

namespace gyrocomp {

namespace {

// A cursor over one message. `origin` is where alignment is measured from (CDR: the first byte
// after the encapsulation header; ROS 1: unused, nothing is aligned).
class Reader {
 public:
  Reader(const std::uint8_t* data, std::size_t size, std::size_t start, std::size_t origin, bool big_endian,
         bool aligned)
      : d_(data), n_(size), pos_(start), origin_(origin), big_(big_endian), aligned_(aligned) {}

  // CORBA 3.3 part 2, 9.3.1.1: a primitive of size s starts at a multiple of s from the origin.
  bool Align(std::size_t s) {
    if (!aligned_) return true;
    const std::size_t rel = pos_ - origin_;
    const std::size_t pad = (s - rel % s) % s;
    if (pad > n_ - pos_) return Fail(pos_, "message ends inside the alignment padding");
    pos_ += pad;
    return true;
  }
  bool Bytes(std::size_t s, std::uint64_t* v, const char* field) {
    if (!Align(s)) return false;
    if (s > n_ - pos_) return Fail(pos_, std::string("message ends inside ") + field);
    std::uint64_t x = 0;
    for (std::size_t i = 0; i < s; ++i) {
      const std::uint64_t b = d_[pos_ + i];
      x |= big_ ? b << (8 * (s - 1 - i)) : b << (8 * i);
    }
    pos_ += s;
    *v = x;
    return true;
  }
  bool U32(std::uint32_t* v, const char* field) {
    std::uint64_t x = 0;
    if (!Bytes(4, &x, field)) return false;
    *v = static_cast<std::uint32_t>(x);
    return true;
  }
  bool F64(double* v, const char* field) {
    std::uint64_t x = 0;
    if (!Bytes(8, &x, field)) return false;
    std::memcpy(v, &x, sizeof *v);
    return true;
  }
  // `count` doubles in a row. After the first is aligned the rest are too (8-byte elements), so
  // the whole array is one bounds check and one copy; an array that does not fit is read element
  // by element so that the error names the byte where it ends, as before.
  bool F64s(double* v, int count, const char* field) {
    const auto bytes = static_cast<std::size_t>(count) * sizeof(double);
    if (!Align(sizeof(double))) return false;
    if (bytes > n_ - pos_) {
      for (int i = 0; i < count; ++i) {
        if (!F64(&v[i], field)) return false;
      }
      return true;
    }
    std::memcpy(v, d_ + pos_, bytes);
    if (big_ != (std::endian::native == std::endian::big)) {
      for (int i = 0; i < count; ++i) v[i] = std::bit_cast<double>(__builtin_bswap64(std::bit_cast<std::uint64_t>(v[i])));
    }
    pos_ += bytes;
    return true;
  }
  // CDR string: uint32 length counting the NUL, the bytes, the NUL (9.3.2.7). ROS 1: uint32
  // length, the bytes, no NUL.
  bool String(bool cdr, const char* field) {
    std::uint32_t len = 0;
    const std::size_t at = pos_;
    if (!U32(&len, field)) return false;
    if (len > n_ - pos_) {
      return Fail(at, std::string(field) + " length " + std::to_string(len) + " runs past the message's end (" +
                          std::to_string(n_ - pos_) + " bytes left)");
    }
    if (cdr && (len == 0 || d_[pos_ + len - 1] != 0)) {
      return Fail(at, std::string(field) + " is not NUL-terminated (CDR strings count their NUL)");
    }
    pos_ += len;
    return true;
  }
  bool Fail(std::size_t at, std::string what) {
    error_ = DecodeError{at, std::move(what)};
    return false;
  }
  std::optional<DecodeError> error() const { return error_; }
  std::size_t pos() const { return pos_; }

 private:
  const std::uint8_t* d_;
  std::size_t n_;
  std::size_t pos_;
  std::size_t origin_;
  bool big_;
  bool aligned_;
  std::optional<DecodeError> error_;
};

// std_msgs/Header: ROS 2 {Time stamp {int32 sec, uint32 nanosec}, string frame_id};
// ROS 1 {uint32 seq, time stamp {uint32 secs, uint32 nsecs}, string frame_id}.
bool ReadHeader(Reader& r, bool ros2, std::int64_t* sec, std::uint32_t* nanosec) {
  std::uint32_t seq = 0, s = 0, ns = 0;
  if (!ros2 && !r.U32(&seq, "header.seq")) return false;
  const std::size_t at = r.pos();
  if (!r.U32(&s, "header.stamp.sec") || !r.U32(&ns, "header.stamp.nanosec")) return false;
  // ROS 2 builtin_interfaces/Time.sec is int32; ROS 1 time.secs is uint32.
  *sec = ros2 ? static_cast<std::int64_t>(static_cast<std::int32_t>(s)) : static_cast<std::int64_t>(s);
  *nanosec = ns;
  if (ns >= 1000000000u) return r.Fail(at + 4, "header.stamp.nanosec = " + std::to_string(ns) + " is not below 1e9");
  return r.String(ros2, "header.frame_id");
}

// The CDR encapsulation header (XTypes 1.3, 7.4.3.5): 0x00 0x00 CDR_BE, 0x00 0x01 CDR_LE.
std::optional<DecodeError> CdrHeader(const std::uint8_t* data, std::size_t size, bool* big_endian) {
  if (size < 4) return DecodeError{0, "message of " + std::to_string(size) + " bytes: no room for the 4-byte CDR encapsulation header"};
  if (data[0] != 0 || data[1] > 1) {
    return DecodeError{0, "encapsulation 0x" + std::to_string(data[0]) + "/" + std::to_string(data[1]) +
                              " is not plain CDR (0x0000 CDR_BE or 0x0001 CDR_LE; XCDR2 / parameter lists are not read)"};
  }
  *big_endian = data[1] == 0;
  return std::nullopt;
}

std::optional<DecodeError> DecodeImu(Reader& r, bool ros2, ImuMessage* out) {
  double orientation[4], cov[9];
  if (!ReadHeader(r, ros2, &out->stamp_sec, &out->stamp_nanosec) ||
      !r.F64s(orientation, 4, "orientation") || !r.F64s(cov, 9, "orientation_covariance") ||
      !r.F64s(out->angular_velocity_rad_s, 3, "angular_velocity") ||
      !r.F64s(cov, 9, "angular_velocity_covariance") ||
      !r.F64s(out->linear_acceleration_m_s2, 3, "linear_acceleration") ||
      !r.F64s(cov, 9, "linear_acceleration_covariance")) {
    return r.error();
  }
  return std::nullopt;
}

std::optional<DecodeError> DecodeTemperature(Reader& r, bool ros2, TemperatureMessage* out) {
  double variance = 0;
  if (!ReadHeader(r, ros2, &out->stamp_sec, &out->stamp_nanosec) || !r.F64(&out->temperature_c, "temperature") ||
      !r.F64(&variance, "variance")) {
    return r.error();
  }
  return std::nullopt;
}

// A writer mirroring Reader (alignment from `origin`).
class Writer {
 public:
  Writer(bool cdr, bool big_endian) : cdr_(cdr), big_(big_endian) {
    if (cdr_) out_ = std::string{'\0', static_cast<char>(big_ ? 0 : 1), '\0', '\0'};
  }
  void Put(std::uint64_t v, std::size_t s) {
    if (cdr_) {
      while ((out_.size() - 4) % s != 0) out_.push_back('\0');
    }
    for (std::size_t i = 0; i < s; ++i) {
      const std::size_t shift = big_ ? 8 * (s - 1 - i) : 8 * i;
      out_.push_back(static_cast<char>((v >> shift) & 0xff));
    }
  }
  void F64(double d) {
    std::uint64_t v;
    std::memcpy(&v, &d, sizeof v);
    Put(v, 8);
  }
  void String(const std::string& s) {
    Put(s.size() + (cdr_ ? 1 : 0), 4);
    out_ += s;
    if (cdr_) out_.push_back('\0');
  }
  void Header(std::int64_t sec, std::uint32_t nanosec, const std::string& frame_id) {
    if (!cdr_) Put(0, 4);  // ROS 1 seq
    Put(static_cast<std::uint32_t>(sec), 4);
    Put(nanosec, 4);
    String(frame_id);
  }
  std::string Take() { return std::move(out_); }

 private:
  bool cdr_, big_;
  std::string out_;
};

std::string EncodeImu(const ImuMessage& m, const std::string& frame_id, bool cdr, bool big_endian) {
  Writer w(cdr, big_endian);
  w.Header(m.stamp_sec, m.stamp_nanosec, frame_id);
  for (double q : {0.0, 0.0, 0.0, 1.0}) w.F64(q);
  for (int i = 0; i < 9; ++i) w.F64(0.0);
  for (double v : m.angular_velocity_rad_s) w.F64(v);
  for (int i = 0; i < 9; ++i) w.F64(0.0);
  for (double v : m.linear_acceleration_m_s2) w.F64(v);
  for (int i = 0; i < 9; ++i) w.F64(0.0);
  return w.Take();
}

std::string EncodeTemperature(const TemperatureMessage& m, const std::string& frame_id, bool cdr, bool big_endian) {
  Writer w(cdr, big_endian);
  w.Header(m.stamp_sec, m.stamp_nanosec, frame_id);
  w.F64(m.temperature_c);
  w.F64(0.0);
  return w.Take();
}

}  // namespace

std::optional<DecodeError> DecodeCdrImu(const std::uint8_t* data, std::size_t size, ImuMessage* out) {
  bool big = false;
  if (auto e = CdrHeader(data, size, &big)) return e;
  Reader r(data, size, 4, 4, big, true);
  return DecodeImu(r, true, out);
}

std::optional<DecodeError> DecodeCdrTemperature(const std::uint8_t* data, std::size_t size, TemperatureMessage* out) {
  bool big = false;
  if (auto e = CdrHeader(data, size, &big)) return e;
  Reader r(data, size, 4, 4, big, true);
  return DecodeTemperature(r, true, out);
}

std::optional<DecodeError> DecodeRos1Imu(const std::uint8_t* data, std::size_t size, ImuMessage* out) {
  Reader r(data, size, 0, 0, false, false);
  return DecodeImu(r, false, out);
}

std::optional<DecodeError> DecodeRos1Temperature(const std::uint8_t* data, std::size_t size, TemperatureMessage* out) {
  Reader r(data, size, 0, 0, false, false);
  return DecodeTemperature(r, false, out);
}

std::string EncodeCdrImu(const ImuMessage& m, const std::string& frame_id, bool big_endian) {
  return EncodeImu(m, frame_id, true, big_endian);
}
std::string EncodeCdrTemperature(const TemperatureMessage& m, const std::string& frame_id, bool big_endian) {
  return EncodeTemperature(m, frame_id, true, big_endian);
}
std::string EncodeRos1Imu(const ImuMessage& m, const std::string& frame_id) { return EncodeImu(m, frame_id, false, false); }
std::string EncodeRos1Temperature(const TemperatureMessage& m, const std::string& frame_id) {
  return EncodeTemperature(m, frame_id, false, false);
}

}  // namespace gyrocomp
