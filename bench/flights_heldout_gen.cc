// Writes one board's logs for bench/calibrate_flights_heldout.py: ten ordinary flight logs, a
// dedicated chamber calibration run and three held-out chamber runs (heating, cooling, warm-up),
// all PX4 ULogs of a 3-IMU board, with the ground truth in truth.json.
//
// Two generators of different structure:
//   1  gyrocomp's own flight simulator (SimulateFlight, gyrocomp/sim/flight.h: the board
//      temperature drives a cubic drift); the chamber runs are built here (first-order chamber
//      lag and self-heating, the same cubic through FlightGyroDriftRadS / FlightAccelDriftM_S2).
//   2  flights_heldout_gen2.cc, written apart from src/sim/flight.cc: a two-node board (board and die, airflow
//      cooling in flight) whose logged temperature is the die thermometer, the MEMS structure
//      lagging it by a second-order lag (two cascaded first-order lags); per-axis curves that are
//      not cubics (tanh, exponential, a smoothed kink, with a sinusoidal ripple); a Gauss-Markov
//      bias wander; attitude from smooth Euler-angle processes; motor vibration as aliased tones
//      plus AR(1) noise; disarmed handling (carried to the take-off spot, a touch while it warms,
//      picked up after landing) that the log's armed / landed state does not show; and the IMU
//      instance order (ULog multi_id) shuffled at every power-on, the device ids staying with
//      the chips (EncodeFlightULog's order).
// Every power-on has its own offset: 0.05 deg/s per gyro axis, 20 mg per accelerometer axis
// (1 sigma). Not part of the CMake build; the script compiles both files against
// build/libgyrocomp.a.
//
// truth.json: per flight, the truly still intervals (log time, s); per sensor (type, IMU, device
// id) the temperature range of the flights' still rows and, on each held-out run, the score of no
// correction and of the least-squares cubic of the true static curve over that range, both as
// `calibrate --validation` scores (PX4 formula in float, T clamped; RMS of 10 s block means,
// their mean removed; the rows read back from the written ULog as 1 s means).
//
// Usage: flights_heldout_gen OUT_DIR GENERATOR(1|2) BOARD SEED [RATE_HZ=50] [LAG_SCALE=1]
// (LAG_SCALE multiplies generator 2's MEMS lag behind the die thermometer; 0: none.)
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "gyrocomp/export/cubic_score.h"
#include "gyrocomp/export/thermal_cubic.h"
#include "gyrocomp/io/ulog.h"
#include "gyrocomp/sim/flight.h"
#include "gyrocomp/sim/simulator.h"

#include "flights_heldout_gen.h"

namespace {

using namespace flights_heldout;
using gyrocomp::FlightRun;

// ---- generator 1 ------------------------------------------------------------------------------
struct Gen1Board {
  std::array<gyrocomp::FlightSimOptions, kImus> imu;  // drift, scales; the flight fields per flight
};

Gen1Board MakeGen1Board(int board) {
  Rng r(7919ULL * static_cast<std::uint64_t>(board) + 11);
  Gen1Board b;
  const double heat = r.U(10.0, 18.0), tau = r.U(300.0, 600.0), air = r.U(5.0, 10.0);
  for (int k = 0; k < kImus; ++k) {
    gyrocomp::FlightSimOptions& o = b.imu[static_cast<std::size_t>(k)];
    o.fs_hz = 50.0;
    o.self_heating_c = heat, o.self_heating_tau_s = tau, o.airflow_cooling_c = air;
    o.gyro_drift_dps = {0.0, r.Sign() * r.U(2e-3, 8e-3), r.Sign() * r.U(0.0, 3e-4), r.Sign() * r.U(0.0, 6e-6)};
    o.accel_drift_m_s2 = {0.0, r.Sign() * r.U(1e-3, 5e-3), r.Sign() * r.U(0.0, 2e-4), r.Sign() * r.U(0.0, 4e-6)};
    o.axis_scale = {r.Sign() * r.U(0.5, 1.0), r.Sign() * r.U(0.5, 1.0), r.Sign() * r.U(0.5, 1.0)};
  }
  return b;
}

Truth Gen1Truth(const Gen1Board& b) {
  Truth t;
  for (int k = 0; k < kImus; ++k)
    for (int a = 0; a < 3; ++a) {
      const gyrocomp::FlightSimOptions o = b.imu[static_cast<std::size_t>(k)];
      t.gyro[k][a] = [o, a](double T) { return gyrocomp::FlightGyroDriftRadS(o, a, T); };
      t.accel[k][a] = [o, a](double T) { return gyrocomp::FlightAccelDriftM_S2(o, a, T); };
    }
  return t;
}

// A chamber run of a generator-1 board: board temperature = first-order lag (300 s) of the
// chamber plus the self-heating (first order from power-on), the cubic of it, offsets, white noise.
std::vector<FlightRun> Gen1Chamber(const Gen1Board& b, const Truth& truth, const ChamberProfile& p, double fs, Rng& r) {
  const auto n = static_cast<std::size_t>(p.Duration() * fs);
  std::vector<FlightRun> out;
  const double roll = r.N() * 2.0 * kRadPerDeg, pitch = r.N() * 2.0 * kRadPerDeg;
  for (int k = 0; k < kImus; ++k) {
    const gyrocomp::FlightSimOptions& o = b.imu[static_cast<std::size_t>(k)];
    FlightRun run = EmptyRun(n, fs);
    std::array<double, 3> g_off, a_off;
    for (int a = 0; a < 3; ++a) g_off[a] = r.N() * o.gyro_offset_dps * kRadPerDeg, a_off[a] = r.N() * o.accel_offset_m_s2;
    const std::array<double, 3> grav = GravityFrd(roll, pitch);
    double board = p.At(0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const double t = run.time_s[i];
      board += (p.At(t) - board) / (300.0 * fs);
      const double T = board + o.self_heating_c * (1.0 - std::exp(-t / o.self_heating_tau_s));
      run.temp_c[i] = T;
      for (int a = 0; a < 3; ++a) {
        run.gyro_rad_s[a][i] = truth.gyro[k][a](T) + g_off[a] + r.N() * o.gyro_noise_dps * kRadPerDeg;
        run.accel_m_s2[a][i] = grav[a] + truth.accel[k][a](T) + a_off[a] + r.N() * o.accel_noise_m_s2;
      }
    }
    out.push_back(std::move(run));
  }
  return out;
}

// ---- scoring the true curve's least-squares cubic like `calibrate --validation` -------------
// The least-squares cubic of f over [lo, hi] (201 equal steps), about the middle (PX4's TREF).
gyrocomp::TemperatureCubic LsqCubic(const Curve& f, double lo, double hi) {
  gyrocomp::TemperatureCubic c;
  c.ref_temp_c = 0.5 * (lo + hi), c.temp_min_c = lo, c.temp_max_c = hi;
  const double s = std::max(0.5 * (hi - lo), 1e-6);
  double A[4][5] = {};
  for (int i = 0; i <= 200; ++i) {
    const double T = lo + (hi - lo) * i / 200.0, u = (T - c.ref_temp_c) / s;
    const double x[4] = {1.0, u, u * u, u * u * u};
    for (int p = 0; p < 4; ++p) {
      for (int q = 0; q < 4; ++q) A[p][q] += x[p] * x[q];
      A[p][4] += x[p] * f(T);
    }
  }
  for (int p = 0; p < 4; ++p) {  // Gauss-Jordan (the system is small and well conditioned)
    for (int q = 0; q < 4; ++q) {
      if (q == p) continue;
      const double k = A[q][p] / A[p][p];
      for (int z = 0; z < 5; ++z) A[q][z] -= k * A[p][z];
    }
  }
  for (int p = 0; p < 4; ++p) c.coeff[static_cast<std::size_t>(p)] = A[p][4] / A[p][p] / std::pow(s, p);
  return c;
}

struct Range {
  double lo = 1e9, hi = -1e9;
};

// The scores on one written held-out log of no correction and of the LS cubic, per sensor (gyro
// IMU 0..2, accel IMU 0..2) and axis, as calibrate --validation computes them (1 s means read,
// 10 s blocks, PX4 formula, the first temperature as the calibration temperature).
std::string ScoreHeldOut(const std::string& path, const Truth& truth, const std::array<Range, kImus>& range) {
  gyrocomp::ULogReadOptions ro;
  ro.average_window_us = 1000000;
  gyrocomp::Result<gyrocomp::ULogContents> log = gyrocomp::ReadULog(path, ro);
  if (!log.ok()) {
    std::fprintf(stderr, "%s\n", log.error().message.c_str());
    std::exit(1);
  }
  std::string json;
  auto score = [&](const char* type, std::uint32_t id, const std::vector<std::uint64_t>& t_us, const std::vector<double>& temp,
                   const std::array<const std::vector<double>*, 3>& v) {
    int imu = -1;
    for (int k = 0; k < kImus; ++k)
      if (id == (type[0] == 'g' ? gyrocomp::BoardGyroDeviceId(k) : gyrocomp::BoardAccelDeviceId(k))) imu = k;
    const double fs = static_cast<double>(t_us.size() - 1) / (static_cast<double>(t_us.back() - t_us.front()) * 1e-6);
    const auto block = static_cast<std::size_t>(std::max(1.0, std::round(10.0 * fs)));
    std::string raw, lsq;
    for (int a = 0; a < 3; ++a) {
      const Curve& f = type[0] == 'g' ? truth.gyro[imu][a] : truth.accel[imu][a];
      const gyrocomp::TemperatureCubic c = LsqCubic(f, range[imu].lo, range[imu].hi);
      const std::vector<double> fw = gyrocomp::FirmwareCorrection(gyrocomp::FirmwareFormula::kPx4, c, temp, temp.front());
      const std::vector<double> zero(temp.size(), 0.0);
      char buf[64];
      std::snprintf(buf, sizeof buf, "%s%.9g", a ? ", " : "", *gyrocomp::ResidualBlockRms(*v[a], zero, block));
      raw += buf;
      std::snprintf(buf, sizeof buf, "%s%.9g", a ? ", " : "", *gyrocomp::ResidualBlockRms(*v[a], fw, block));
      lsq += buf;
    }
    json += std::string(json.empty() ? "" : ", ") + "{\"type\": \"" + type + "\", \"imu\": " + std::to_string(imu) +
            ", \"device_id\": " + std::to_string(id) + ", \"raw\": [" + raw + "], \"lsq\": [" + lsq + "]}";
  };
  for (const auto& g : log->gyros) score("gyro", *g.device_id, g.timestamp_us, g.temperature_c, {&g.x_rad_s, &g.y_rad_s, &g.z_rad_s});
  for (const auto& a : log->accels) score("accel", *a.device_id, a.timestamp_us, a.temperature_c, {&a.x_m_s2, &a.y_m_s2, &a.z_m_s2});
  return "[" + json + "]";
}

void Write(const std::string& path, const std::vector<FlightRun>& imus, const std::vector<int>& order) {
  gyrocomp::Result<std::string> bytes = gyrocomp::EncodeFlightULog(imus, 1, order);
  if (!bytes.ok()) {
    std::fprintf(stderr, "%s\n", bytes.error().message.c_str());
    std::exit(1);
  }
  std::ofstream(path, std::ios::binary).write(bytes->data(), static_cast<std::streamsize>(bytes->size()));
}

// The truly still intervals of a run in log time (EncodeFlightULog: logging starts at 1 s),
// each [first row, last row + 1 / fs, then per IMU the lowest and highest logged temperature].
std::string StillIntervals(const std::vector<FlightRun>& imus, double fs) {
  const FlightRun& r = imus.front();
  std::string out;
  for (std::size_t i = 0; i < r.truly_still.size();) {
    if (!r.truly_still[i]) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < r.truly_still.size() && r.truly_still[j]) ++j;
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s[%.6f, %.6f", out.empty() ? "" : ", ", r.time_s[i] + 1.0, r.time_s[j - 1] + 1.0 + 1.0 / fs);
    out += buf;
    for (const FlightRun& m : imus) {
      const auto [lo, hi] = std::minmax_element(m.temp_c.begin() + static_cast<std::ptrdiff_t>(i), m.temp_c.begin() + static_cast<std::ptrdiff_t>(j));
      std::snprintf(buf, sizeof buf, ", %.4f, %.4f", *lo, *hi);
      out += buf;
    }
    out += "]";
    i = j;
  }
  return "[" + out + "]";
}

std::vector<int> Order(Rng& r, bool shuffle) {
  std::vector<int> o = {0, 1, 2};
  if (shuffle) std::shuffle(o.begin(), o.end(), r.e);
  return o;
}

// Generator 1's IMUs of one flight (SimulateFlight per IMU, seeds seed + i), each from the
// board's options with the flight's timing; `tweak` may change the options further. False with
// the message on stderr when the simulator refuses them.
bool Gen1Flight(const Gen1Board& b, double fs, double ambient_c, double still_before_s, double flight_s,
                double still_after_s, std::uint64_t seed, const std::function<void(gyrocomp::FlightSimOptions&)>& tweak,
                std::vector<FlightRun>* imus) {
  for (int i = 0; i < kImus; ++i) {
    gyrocomp::FlightSimOptions o = b.imu[static_cast<std::size_t>(i)];
    o.fs_hz = fs, o.ambient_c = ambient_c, o.still_before_s = still_before_s, o.flight_s = flight_s,
    o.still_after_s = still_after_s;
    if (tweak) tweak(o);
    o.seed = seed + static_cast<std::uint64_t>(i);
    gyrocomp::Result<FlightRun> run = gyrocomp::SimulateFlight(o);
    if (!run.ok()) {
      std::fprintf(stderr, "%s\n", run.error().message.c_str());
      return false;
    }
    imus->push_back(std::move(*run));
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: %s OUT_DIR GENERATOR(1|2) BOARD SEED [RATE_HZ=50]\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  const int gen = std::atoi(argv[2]), board = std::atoi(argv[3]);
  const auto seed = static_cast<std::uint64_t>(std::atoll(argv[4]));
  const double fs = argc > 5 ? std::atof(argv[5]) : 50.0;
  Rng r(seed * 1000003ULL + static_cast<std::uint64_t>(gen) * 101ULL + static_cast<std::uint64_t>(board));
  Truth truth;
  Gen1Board b1;
  Gen2Board b2;
  if (gen == 1) {
    b1 = MakeGen1Board(board);
    truth = Gen1Truth(b1);
  } else {
    b2 = MakeGen2Board(board, &truth, argc > 6 ? std::atof(argv[6]) : 1.0);
  }
  // Ambients spread over 0..35 C, in a shuffled order.
  std::vector<double> ambient(kFlights);
  for (int k = 0; k < kFlights; ++k) ambient[static_cast<std::size_t>(k)] = 35.0 * k / (kFlights - 1) + r.U(-1.5, 1.5);
  std::shuffle(ambient.begin(), ambient.end(), r.e);
  std::array<Range, kImus> range;
  // Ten ordinary flights, then three quick hops at one ambient (for the three-log check: too
  // little still time and change to identify a curve).
  std::string flights_json, quick_json;
  for (int k = 0; k < kFlights + 3; ++k) {
    std::vector<FlightRun> imus;
    const bool quick = k >= kFlights;
    const double amb = quick ? 20.0 + r.U(-1.0, 1.0) : ambient[static_cast<std::size_t>(k)];
    double pre_still_s = 0.0;
    if (gen == 1) {
      const double still_before = quick ? r.U(30.0, 60.0) : r.U(60.0, 600.0), flight = quick ? 300.0 : r.U(300.0, 1200.0),
                   after = quick ? r.U(20.0, 40.0) : r.U(120.0, 600.0);
      if (!Gen1Flight(b1, fs, amb, still_before, flight, after, r.e(), {}, &imus)) return 1;
      pre_still_s = still_before;
    } else {
      const Motion m = Gen2Timeline(fs, r, quick);
      const double drift_c_per_s = r.U(-1.0, 1.0) / 3600.0;  // outdoor air changing by up to 1 C an hour
      imus = Gen2Run(b2, truth, m, [=](double t) { return amb + drift_c_per_s * t; }, fs, r);
      std::size_t first_motion = 0;
      while (first_motion < m.still.size() && m.still[first_motion]) ++first_motion;
      pre_still_s = static_cast<double>(first_motion) / fs;
    }
    for (int i = 0; i < kImus && !quick; ++i)
      for (std::size_t j = 0; j < imus[static_cast<std::size_t>(i)].temp_c.size(); ++j)
        if (imus[0].truly_still[j]) {
          const double T = imus[static_cast<std::size_t>(i)].temp_c[j];
          range[i].lo = std::min(range[i].lo, T), range[i].hi = std::max(range[i].hi, T);
        }
    const std::vector<int> order = Order(r, gen == 2);
    const std::string name = quick ? "quick" + std::to_string(k - kFlights) + ".ulg" : "flight" + std::to_string(k) + ".ulg";
    Write(dir + "/" + name, imus, order);
    char head[256];
    std::snprintf(head, sizeof head, "{\"path\": \"%s\", \"ambient_c\": %.3f, \"power_on_still_s\": %.3f, \"rows\": %zu, \"order\": [%d, %d, %d], \"still\": ",
                  name.c_str(), amb, pre_still_s, imus[0].time_s.size(), order[0], order[1], order[2]);
    std::string& list = quick ? quick_json : flights_json;
    list += std::string(list.empty() ? "" : ",\n  ") + head + StillIntervals(imus, fs) + "}";
  }
  // The chamber runs: the dedicated calibration, then the held-out ones.
  std::string held_json;
  std::vector<ChamberProfile> runs = {kCalibration};
  runs.insert(runs.end(), kHeldOut.begin(), kHeldOut.end());
  for (std::size_t p = 0; p < runs.size(); ++p) {
    const ChamberProfile& prof = runs[p];
    std::vector<FlightRun> imus;
    if (gen == 1) {
      imus = Gen1Chamber(b1, truth, prof, fs, r);
    } else {
      const Motion m = StillMotion(static_cast<std::size_t>(prof.Duration() * fs), r);
      imus = Gen2Run(b2, truth, m, [prof](double t) { return prof.At(t); }, fs, r);
    }
    const std::string name = (p == 0 ? std::string("chamber_cal") : "heldout_" + prof.name) + ".ulg";
    Write(dir + "/" + name, imus, Order(r, gen == 2));
    if (p > 0)
      held_json += std::string(held_json.empty() ? "" : ",\n  ") + "{\"name\": \"" + prof.name + "\", \"path\": \"" + name +
                   "\", \"sensors\": " + ScoreHeldOut(dir + "/" + name, truth, range) + "}";
  }
  // Three restarts that barely warm (for the three-log check: still time enough, too little
  // change inside a log), from their own random stream so the logs above do not change.
  // Generator 1: a board that self-heats 2 C and cools 1.5 C in flight; generator 2: the same
  // board restarted at its self-heated temperature.
  Rng w(seed * 7777ULL + static_cast<std::uint64_t>(gen) * 13ULL + static_cast<std::uint64_t>(board));
  std::string warm_json;
  for (int k = 0; k < 3; ++k) {
    const double amb = 20.0 + w.U(-1.0, 1.0);
    std::vector<FlightRun> imus;
    if (gen == 1) {
      const double still_before = w.U(240.0, 360.0), after = w.U(120.0, 180.0);
      const auto barely_warms = [](gyrocomp::FlightSimOptions& o) { o.self_heating_c = 2.0, o.airflow_cooling_c = 1.5; };
      if (!Gen1Flight(b1, fs, amb, still_before, 120.0, after, w.e(), barely_warms, &imus)) return 1;
    } else {
      const Motion m = Gen2Timeline(fs, w, false, true);
      imus = Gen2Run(b2, truth, m, [=](double) { return amb; }, fs, w, /*warm_start=*/true);
    }
    const std::vector<int> order = Order(w, gen == 2);
    const std::string name = "warm" + std::to_string(k) + ".ulg";
    Write(dir + "/" + name, imus, order);
    char head[256];
    std::snprintf(head, sizeof head, "{\"path\": \"%s\", \"ambient_c\": %.3f, \"rows\": %zu, \"order\": [%d, %d, %d], \"still\": ",
                  name.c_str(), amb, imus[0].time_s.size(), order[0], order[1], order[2]);
    warm_json += std::string(warm_json.empty() ? "" : ",\n  ") + head + StillIntervals(imus, fs) + "}";
  }
  std::string ranges;
  for (int i = 0; i < kImus; ++i)
    ranges += (i ? ", " : "") + std::string("[") + std::to_string(range[i].lo) + ", " + std::to_string(range[i].hi) + "]";
  std::ofstream(dir + "/truth.json") << "{\"generator\": " << gen << ", \"board\": " << board << ", \"seed\": " << seed
                                     << ", \"rate_hz\": " << fs << ",\n \"flight_still_range_c\": [" << ranges
                                     << "],\n \"flights\": [" << flights_json << "],\n \"quick\": [" << quick_json << "],\n \"warm\": [" << warm_json
                                     << "],\n \"heldout\": [" << held_json << "]}\n";
  return 0;
}
