// Generator of the C99 drift evaluator (see c_export.h). The generated arithmetic mirrors
// PredictDriftCausal / CausalRateStep / PolynomialModel::Predict / SvrModel::PredictOne operation
// for operation, so the double build agrees with the library to rounding.
#include "gyrocomp/export/c_export.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace gyrocomp {
namespace {

// Shortest text that reads back to the same double, as a typed constant: ((P_real)x).
std::string Num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  std::string s = buf;
  if (s.find_first_of(".eE") == std::string::npos) s += ".0";
  return s;
}

struct Names {
  std::string p;      // lower-case prefix
  std::string P;      // upper-case prefix (macros)
  std::string real;   // <p>_real
  std::string R(double v) const { return "((" + real + ")" + Num(v) + ")"; }
};

bool IsCIdentifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

bool UsesRate(const DriftModel& m) { return UsesCausalRate(m.inputs); }
// Eq. TS-3 carried in state->mem: as the state (temp,memory) or as the second state (temp,dtemp,memory).
bool UsesMemory(const DriftModel& m) {
  return m.inputs == DriftInputSet::kTempAndMemory || HasSecondMemoryState(m.inputs);
}
bool UsesState(const DriftModel& m) { return m.inputs != DriftInputSet::kTemp; }
bool IsSvr(const DriftModel& m) { return m.kernel.has_value(); }

Status CheckFinite(const AxisDriftModel& a) {
  auto bad = [&](double v) { return !std::isfinite(v); };
  const DriftFitSummary& s = a.model.summary;
  bool any = bad(s.temp_min_c) || bad(s.temp_max_c) || bad(s.dtemp_min_c_per_s) || bad(s.dtemp_max_c_per_s);
  if (const auto& p = a.model.structured) {
    for (const auto& t : p->terms) any = any || bad(t.coefficient);
    for (double v : p->input_scaler.offset) any = any || bad(v);
    for (double v : p->input_scaler.scale) any = any || bad(v);
  }
  if (const auto& m = a.model.kernel) {
    for (double v : m->support_vectors) any = any || bad(v);
    for (double v : m->coefficients) any = any || bad(v);
    any = any || bad(m->gamma) || bad(m->intercept) || bad(m->target_offset) || bad(m->target_scale);
  }
  const ThermalStateOptions& st = a.model.state;
  any = any || bad(st.causal_rate_tau_s) || bad(st.lag_tau_s) || bad(st.memory_width_c) ||
        bad(st.memory_deadband_c_per_s);
  if (!a.model.structured && !a.model.kernel)
    return InvalidInput("C export: axis '" + a.axis + "' has neither a structured nor a kernel part");
  if (any) return InvalidInput("C export: axis '" + a.axis + "' has a non-finite number in its model");
  return Status::Ok();
}

// "static P_real <p>_aK_poly(P_real temp_c, P_real dtemp, P_real mem)" for a polynomial model
// (mem: the second state of temp,dtemp,memory; unused otherwise).
void EmitPolynomial(std::ostringstream& s, const Names& n, int k, const PolynomialModel& m, bool rate) {
  int max_t = 0, max_r = 0;
  bool any_m = false;
  for (const auto& t : m.terms) {
    max_t = std::max(max_t, t.temp_power);
    max_r = std::max(max_r, t.dtemp_power);
    any_m = any_m || t.memory_power > 0;
  }
  const std::string a = n.p + "_a" + std::to_string(k);
  s << "static " << n.real << " " << a << "_poly(" << n.real << " temp_c, " << n.real << " dtemp, " << n.real
    << " mem) {\n";
  s << "  " << n.real << " tp[" << max_t + 1 << "], rp[" << max_r + 1 << "];\n  " << n.real << " f = "
    << n.R(0.0) << ";\n  int i;\n";
  s << "  const " << n.real << " t = (temp_c - " << n.R(m.input_scaler.offset[0]) << ") / "
    << n.R(m.input_scaler.scale[0]) << ";\n";
  if (rate && m.input_scaler.offset.size() > 1)
    s << "  const " << n.real << " r = (dtemp - " << n.R(m.input_scaler.offset[1]) << ") / "
      << n.R(m.input_scaler.scale[1]) << ";\n";
  else
    s << "  const " << n.real << " r = " << n.R(0.0) << ";\n  (void)dtemp;\n";
  if (any_m && m.input_scaler.offset.size() > 2)  // PolynomialModel::PredictOne's m
    s << "  const " << n.real << " m = (mem - " << n.R(m.input_scaler.offset[2]) << ") / "
      << n.R(m.input_scaler.scale[2]) << ";\n";
  else
    s << "  (void)mem;\n";
  s << "  tp[0] = " << n.R(1.0) << ";\n  rp[0] = " << n.R(1.0) << ";\n";
  s << "  for (i = 1; i <= " << max_t << "; ++i) tp[i] = tp[i - 1] * t;\n";
  s << "  for (i = 1; i <= " << max_r << "; ++i) rp[i] = rp[i - 1] * r;\n";
  // sum_k c_k t^p_k r^q_k, in the library's order.
  for (const auto& t : m.terms) {
    s << "  f += " << n.R(t.coefficient) << " * tp[" << t.temp_power << "] * rp[" << t.dtemp_power << "]";
    s << (t.memory_power > 0 && any_m && m.input_scaler.offset.size() > 2 ? " * m;\n" : ";\n");
  }
  s << "  return f;\n}\n\n";
}

// The same for an RBF SVR: Eq. (23) with the scalers of svr.h.
void EmitSvr(std::ostringstream& s, const Names& n, int k, const SvrModel& m) {
  const std::string a = n.p + "_a" + std::to_string(k);
  const std::size_t nin = m.num_inputs, nsv = m.num_support();
  if (nsv > 0) {
    s << "static const " << n.real << " " << a << "_sv[" << nsv * nin << "] = {";
    for (std::size_t i = 0; i < m.support_vectors.size(); ++i) s << (i % 4 ? " " : "\n  ") << Num(m.support_vectors[i]) << ",";
    s << "\n};\nstatic const " << n.real << " " << a << "_coef[" << nsv << "] = {";
    for (std::size_t i = 0; i < nsv; ++i) s << (i % 4 ? " " : "\n  ") << Num(m.coefficients[i]) << ",";
    s << "\n};\n\n";
  }
  s << "static " << n.real << " " << a << "_svr(" << n.real << " temp_c, " << n.real << " dtemp, " << n.real
    << " mem) {\n";
  s << "  " << n.real << " z[" << nin << "];\n  " << n.real << " f = " << n.R(m.intercept) << ";\n";
  s << "  z[0] = (temp_c - " << n.R(m.input_scaler.offset[0]) << ") / " << n.R(m.input_scaler.scale[0]) << ";\n";
  if (nin > 1)
    s << "  z[1] = (dtemp - " << n.R(m.input_scaler.offset[1]) << ") / " << n.R(m.input_scaler.scale[1]) << ";\n";
  else
    s << "  (void)dtemp;\n";
  if (nin > 2)
    s << "  z[2] = (mem - " << n.R(m.input_scaler.offset[2]) << ") / " << n.R(m.input_scaler.scale[2]) << ";\n";
  else
    s << "  (void)mem;\n";
  if (nsv > 0) {
    // Compensated (Kahan) sum: the terms cancel (|sum| << sum |terms|), which float alone would
    // not survive (docs/explanation/flight-controller-export.md). Do not compile with -ffast-math: it removes the compensation.
    s << "  {\n    int i, j;\n    " << n.real << " comp = " << n.R(0.0) << ";\n    for (i = 0; i < " << nsv
      << "; ++i) {\n      " << n.real << " d2 = " << n.R(0.0) << ", term, y, sum;\n      for (j = 0; j < " << nin
      << "; ++j) {\n        const " << n.real << " d = z[j] - " << a << "_sv[i * " << nin
      << " + j];\n        d2 += d * d;\n      }\n      term = " << a << "_coef[i] * " << n.P << "_EXP("
      << n.R(-m.gamma) << " * d2);\n      y = term - comp;\n      sum = f + y;\n      comp = (sum - f) - y;\n"
      << "      f = sum;\n    }\n  }\n";
  } else {
    s << "  (void)z;\n";
  }
  s << "  return " << n.R(m.target_offset) << " + " << n.R(m.target_scale) << " * f;\n}\n\n";
}

std::string Header(const std::vector<AxisDriftModel>& axes, const CExportOptions& o, const Names& n) {
  std::ostringstream s;
  s << "/* " << n.p << ".h: temperature-drift compensation generated by gyrocomp export --format c.\n";
  for (const std::string& c : o.comments) s << " * " << c << "\n";
  s << " * Rates in " << o.output_unit << ", temperatures in deg C, times in s. C99, no allocation.\n"
    << " * Define " << n.P << "_USE_FLOAT for a float-only build. Do not edit: regenerate. */\n";
  s << "#ifndef " << n.P << "_H\n#define " << n.P << "_H\n\n";
  s << "#ifdef " << n.P << "_USE_FLOAT\ntypedef float " << n.real << ";\n#else\ntypedef double " << n.real
    << ";\n#endif\n\n#define " << n.P << "_NUM_AXES " << axes.size() << "\n\n";
  s << "/* Axes, in rate_in / rate_out order:\n";
  for (std::size_t k = 0; k < axes.size(); ++k)
    s << " *   " << k << " = " << axes[k].axis << " (" << DriftModelKindName(axes[k].model.kind) << ", "
      << DriftInputSetName(axes[k].model.inputs) << ", fitted on T in [" << axes[k].model.summary.temp_min_c << ", "
      << axes[k].model.summary.temp_max_c << "] C, out of range: " << OutOfRangePolicyName(axes[k].model.out_of_range)
      << ")\n";
  s << " */\ntypedef struct {\n  int initialized;\n"
    << "  " << n.real << " prev_c[" << axes.size() << "];  /* previous temperature, deg C */\n"
    << "  " << n.real << " e1_c[" << axes.size() << "];    /* T minus the first rate lag L1, deg C */\n"
    << "  " << n.real << " d_c[" << axes.size() << "];     /* L1 minus the second rate lag L2, deg C */\n"
    << "  " << n.real << " lag_c[" << axes.size() << "];   /* T minus the die lag T_lag, deg C */\n"
    << "  " << n.real << " mem[" << axes.size() << "];     /* heating (+1) / cooling (-1) memory */\n"
    << "  " << n.real << " drift[" << axes.size() << "];   /* last drift subtracted, " << o.output_unit << " */\n"
    << "} " << n.p << "_state;\n\n";
  s << "void " << n.p << "_init(" << n.p << "_state *state);\n";
  s << "/* One sample: dt_s since the previous call (ignored on the first), the sensor temperature,\n"
       " * the measured rates; writes rate_out = rate_in - drift (rate_out may alias rate_in). */\n";
  s << "void " << n.p << "_step(" << n.p << "_state *state, " << n.real << " dt_s, " << n.real << " temp_c,\n"
    << "    const " << n.real << " *rate_in, " << n.real << " *rate_out);\n\n#endif\n";
  return s.str();
}

void EmitPrelude(std::ostringstream& s, const std::vector<AxisDriftModel>& axes, const Names& n) {
  bool any_exp = false, any_rate = false, any_lag = false;
  for (const auto& a : axes) {
    any_exp = any_exp || IsSvr(a.model) || UsesState(a.model);
    any_rate = any_rate || UsesRate(a.model);
    any_lag = any_lag || a.model.inputs == DriftInputSet::kTempAndLag;
  }
  s << "/* " << n.p << ".c: generated by gyrocomp export --format c (see " << n.p << ".h). */\n";
  s << "#include \"" << n.p << ".h\"\n\n";
  if (any_exp)
    s << "#include <math.h>\n\n#ifdef " << n.P << "_USE_FLOAT\n#define " << n.P << "_EXP expf\n#else\n#define "
      << n.P << "_EXP exp\n#endif\n\n";
  const std::string& r = n.real;
  if (any_rate) {
    // Eq. TS-1 of thermal_state.h, carried as small numbers (T_{k-1}, T - L1, L1 - L2).
    s << "/* Causal dT/dt (thermal_state.h Eq. TS-1): two lags, a = 1 - exp(-dt/tau), estimate\n"
         " * (L1 - L2) / d, d = dt / (exp(dt/tau) - 1), carried as T_{k-1}, T - L1 and L1 - L2. */\n";
    s << "static " << r << " " << n.p << "_rate_step(" << r << " *prev, " << r << " *e1, " << r
      << " *d, int initialized, " << r << " dt_s, " << r << " temp_c, " << r << " tau_s) {\n";
    s << "  " << r << " b, a, x;\n  if (!initialized) {\n    *prev = temp_c;\n    *e1 = " << n.R(0.0)
      << ";\n    *d = " << n.R(0.0) << ";\n    return " << n.R(0.0) << ";\n  }\n";
    s << "  if (!(dt_s > " << n.R(0.0) << ")) return *d / tau_s;\n"
      << "  b = " << n.P << "_EXP(-dt_s / tau_s);\n  a = " << n.R(1.0) << " - b;\n"
      << "  x = (temp_c - *prev) + *e1;\n  *prev = temp_c;\n  *e1 = b * x;\n  *d = b * (*d + a * x);\n"
      << "  /* (L1 - L2) / d written as D a / (b dt): unbiased by the rounding of a and b */\n"
      << "  return *d * a / (b * dt_s);\n}\n\n";
  }
  if (any_lag) {
    s << "/* Lag state (Eq. TS-2): s = T - T_lag, carried as T_{k-1} and s. */\n";
    s << "static " << r << " " << n.p << "_lag_step(" << r << " *prev, " << r << " *lag, int initialized, " << r
      << " dt_s, " << r << " temp_c, " << r << " tau_s) {\n";
    s << "  if (!initialized) {\n    *prev = temp_c;\n    *lag = " << n.R(0.0) << ";\n    return " << n.R(0.0)
      << ";\n  }\n  *lag = " << n.P << "_EXP(-dt_s / tau_s) * ((temp_c - *prev) + *lag);\n"
      << "  *prev = temp_c;\n  return *lag;\n}\n\n";
  }
}

// The axis's model function: structured part + kernel part (DriftModel::PredictAt's order).
void EmitAxisEval(std::ostringstream& s, const Names& n, int k, const DriftModel& m) {
  const std::string a = n.p + "_a" + std::to_string(k);
  s << "static " << n.real << " " << a << "_eval(" << n.real << " temp_c, " << n.real << " state, " << n.real
    << " mem) {\n";
  s << "  " << n.real << " f = " << n.R(0.0) << ";\n";
  if (m.structured) s << "  f += " << a << "_poly(temp_c, state, mem);\n";
  if (m.kernel) s << "  f += " << a << "_svr(temp_c, state, mem);\n";
  s << "  return f;\n}\n\n";
}

// Eq. TS-3 on the rate r of Eq. TS-1 (ThermalStateEvaluator::Step), into state->mem[k].
void EmitMemoryUpdate(std::ostringstream& s, const Names& n, const std::string& K, const ThermalStateOptions& o) {
  s << "  if (!state->initialized) {\n    state->mem[" << K << "] = " << n.R(0.0)
    << ";\n  } else if ((r < " << n.R(0.0) << " ? -r : r) > " << n.R(o.memory_deadband_c_per_s) << ") {\n"
    << "    " << n.real << " g = (r < " << n.R(0.0) << " ? -r : r) * dt_s / " << n.R(o.memory_width_c) << ";\n"
    << "    if (g > " << n.R(1.0) << ") g = " << n.R(1.0) << ";\n"
    << "    state->mem[" << K << "] += g * ((r > " << n.R(0.0) << " ? " << n.R(1.0) << " : " << n.R(-1.0)
    << ") - state->mem[" << K << "]);\n  }\n";
}

// The thermal state of axis k after this sample (ThermalStateEvaluator::Step), into `st` (and
// the second state of temp,dtemp,memory into `mt`; 0 otherwise).
void EmitState(std::ostringstream& s, const Names& n, std::size_t k, const DriftModel& m) {
  const ThermalStateOptions& o = m.state;
  const std::string K = std::to_string(k);
  const std::string rate_call = n.p + "_rate_step(&state->prev_c[" + K + "], &state->e1_c[" + K +
                                "], &state->d_c[" + K + "], state->initialized, dt_s, temp_c, " +
                                n.R(o.causal_rate_tau_s) + ")";
  switch (m.inputs) {
    case DriftInputSet::kTemp:
      s << "  st = " << n.R(0.0) << ";\n";
      break;
    case DriftInputSet::kTempAndRate:
      s << "  st = " << rate_call << ";\n";
      break;
    case DriftInputSet::kTempAndLag:
      s << "  st = " << n.p << "_lag_step(&state->prev_c[" << K << "], &state->lag_c[" << K
        << "], state->initialized, dt_s, temp_c, " << n.R(o.lag_tau_s) << ");\n";
      break;
    case DriftInputSet::kTempAndMemory:  // Eq. TS-3 on the rate of Eq. TS-1
      s << "  r = " << rate_call << ";\n";
      EmitMemoryUpdate(s, n, K, o);
      s << "  st = state->mem[" << K << "];\n";
      break;
    case DriftInputSet::kTempRateAndMemory:  // both: s = r (Eq. TS-1), mt = m (Eq. TS-3)
      s << "  r = " << rate_call << ";\n";
      EmitMemoryUpdate(s, n, K, o);
      s << "  st = r;\n  mt = state->mem[" << K << "];\n";
      break;
  }
  if (!HasSecondMemoryState(m.inputs)) s << "  mt = " << n.R(0.0) << ";\n";
}

void EmitStep(std::ostringstream& s, const std::vector<AxisDriftModel>& axes, const CExportOptions& o, const Names& n) {
  s << "void " << n.p << "_init(" << n.p << "_state *state) {\n  int a;\n  state->initialized = 0;\n"
    << "  for (a = 0; a < " << n.P << "_NUM_AXES; ++a) {\n";
  for (const char* f : {"prev_c", "e1_c", "d_c", "lag_c", "mem", "drift"}) s << "    state->" << f << "[a] = " << n.R(0.0) << ";\n";
  s << "  }\n}\n\n";
  s << "void " << n.p << "_step(" << n.p << "_state *state, " << n.real << " dt_s, " << n.real << " temp_c,\n"
    << "    const " << n.real << " *rate_in, " << n.real << " *rate_out) {\n";
  bool any_state = false, any_memory = false;
  for (const auto& a : axes) {
    any_state = any_state || UsesState(a.model);
    any_memory = any_memory || UsesMemory(a.model);
  }
  s << "  " << n.real << " t, st, mt;\n";
  if (any_memory) s << "  " << n.real << " r;\n";
  if (!any_state) s << "  (void)dt_s;\n";
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const DriftModel& m = axes[k].model;
    s << "  /* axis " << k << ": " << axes[k].axis << " (" << DriftModelKindName(m.kind) << ", "
      << DriftInputSetName(m.inputs) << ", out of range: " << OutOfRangePolicyName(m.out_of_range) << ") */\n";
    EmitState(s, n, k, m);
    s << "  t = temp_c;\n";
    if (m.out_of_range == OutOfRangePolicy::kClamp)  // DriftModel::EffectiveTemp; the state is never clamped
      s << "  if (t < " << n.R(m.temp_min_c()) << ") t = " << n.R(m.temp_min_c()) << ";\n  else if (t > "
        << n.R(m.temp_max_c()) << ") t = " << n.R(m.temp_max_c()) << ";\n";
    s << "  state->drift[" << k << "] = " << n.R(o.output_scale) << " * " << n.p << "_a" << k << "_eval(t, st, mt);\n";
    s << "  rate_out[" << k << "] = rate_in[" << k << "] - state->drift[" << k << "];\n";
  }
  s << "  state->initialized = 1;\n}\n";
}

}  // namespace

bool CExportOptions::IsValid(std::string* error) const {
  if (!IsCIdentifier(prefix)) {
    if (error) *error = "CExportOptions::prefix = '" + prefix + "': must be a C identifier ([A-Za-z_][A-Za-z0-9_]*)";
    return false;
  }
  if (!(output_scale > 0.0) || !std::isfinite(output_scale)) {
    if (error) *error = "CExportOptions::output_scale must be > 0";
    return false;
  }
  return true;
}

Result<GeneratedC> GenerateCEvaluator(const std::vector<AxisDriftModel>& axes, const CExportOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) return InvalidArgument(why);
  if (axes.empty()) return InvalidArgument("C export: no axis model given");
  for (const auto& a : axes)
    if (Status st = CheckFinite(a); !st.ok()) return st.error();
  Names n;
  n.p = o.prefix;
  for (char c : o.prefix) n.P += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  n.real = n.p + "_real";
  GeneratedC out;
  out.header_name = n.p + ".h";
  out.source_name = n.p + ".c";
  out.header = Header(axes, o, n);
  std::ostringstream s;
  EmitPrelude(s, axes, n);
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const DriftModel& m = axes[k].model;
    if (m.structured) EmitPolynomial(s, n, static_cast<int>(k), *m.structured, UsesState(m));
    if (m.kernel) EmitSvr(s, n, static_cast<int>(k), *m.kernel);
    EmitAxisEval(s, n, static_cast<int>(k), m);
  }
  EmitStep(s, axes, o, n);
  out.source = s.str();
  return out;
}

}  // namespace gyrocomp
