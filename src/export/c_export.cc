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

bool UsesRate(const DriftModel& m) { return m.inputs == DriftInputSet::kTempAndRate; }
bool IsSvr(const DriftModel& m) { return m.kernel.has_value(); }

Status CheckFinite(const AxisDriftModel& a) {
  auto bad = [&](double v) { return !std::isfinite(v); };
  const DriftFitSummary& s = a.model.summary;
  bool any = bad(s.temp_min_c) || bad(s.temp_max_c) || bad(s.dtemp_min_c_per_s) || bad(s.dtemp_max_c_per_s);
  if (const PolynomialModel* p = a.model.structured ? &*a.model.structured : nullptr) {
    for (const auto& t : p->terms) any = any || bad(t.coefficient);
    for (double v : p->input_scaler.offset) any = any || bad(v);
    for (double v : p->input_scaler.scale) any = any || bad(v);
  } else {
    const SvrModel& m = *a.model.kernel;
    for (double v : m.support_vectors) any = any || bad(v);
    for (double v : m.coefficients) any = any || bad(v);
    any = any || bad(m.gamma) || bad(m.intercept) || bad(m.target_offset) || bad(m.target_scale);
  }
  if (any) return InvalidInput("C export: axis '" + a.axis + "' has a non-finite number in its model");
  return Status::Ok();
}

// "static P_real <p>_aK_eval(P_real temp_c, P_real dtemp)" for a polynomial model.
void EmitPolynomial(std::ostringstream& s, const Names& n, int k, const PolynomialModel& m, bool rate) {
  int max_t = 0, max_r = 0;
  for (const auto& t : m.terms) {
    max_t = std::max(max_t, t.temp_power);
    max_r = std::max(max_r, t.dtemp_power);
  }
  const std::string a = n.p + "_a" + std::to_string(k);
  s << "static " << n.real << " " << a << "_eval(" << n.real << " temp_c, " << n.real << " dtemp) {\n";
  s << "  " << n.real << " tp[" << max_t + 1 << "], rp[" << max_r + 1 << "];\n  " << n.real << " f = "
    << n.R(0.0) << ";\n  int i;\n";
  s << "  const " << n.real << " t = (temp_c - " << n.R(m.input_scaler.offset[0]) << ") / "
    << n.R(m.input_scaler.scale[0]) << ";\n";
  if (rate && m.input_scaler.offset.size() > 1)
    s << "  const " << n.real << " r = (dtemp - " << n.R(m.input_scaler.offset[1]) << ") / "
      << n.R(m.input_scaler.scale[1]) << ";\n";
  else
    s << "  const " << n.real << " r = " << n.R(0.0) << ";\n  (void)dtemp;\n";
  s << "  tp[0] = " << n.R(1.0) << ";\n  rp[0] = " << n.R(1.0) << ";\n";
  s << "  for (i = 1; i <= " << max_t << "; ++i) tp[i] = tp[i - 1] * t;\n";
  s << "  for (i = 1; i <= " << max_r << "; ++i) rp[i] = rp[i - 1] * r;\n";
  // sum_k c_k t^p_k r^q_k, in the library's order.
  for (const auto& t : m.terms)
    s << "  f += " << n.R(t.coefficient) << " * tp[" << t.temp_power << "] * rp[" << t.dtemp_power << "];\n";
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
  s << "static " << n.real << " " << a << "_eval(" << n.real << " temp_c, " << n.real << " dtemp) {\n";
  s << "  " << n.real << " z[" << nin << "];\n  " << n.real << " f = " << n.R(m.intercept) << ";\n";
  s << "  z[0] = (temp_c - " << n.R(m.input_scaler.offset[0]) << ") / " << n.R(m.input_scaler.scale[0]) << ";\n";
  if (nin > 1)
    s << "  z[1] = (dtemp - " << n.R(m.input_scaler.offset[1]) << ") / " << n.R(m.input_scaler.scale[1]) << ";\n";
  else
    s << "  (void)dtemp;\n";
  if (nsv > 0) {
    // Compensated (Kahan) sum: the terms cancel (|sum| << sum |terms|), which float alone would
    // not survive (docs/export.md). Do not compile with -ffast-math: it removes the compensation.
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
      << DriftInputSetName(axes[k].model.inputs) << ", T clamped to [" << axes[k].model.summary.temp_min_c << ", "
      << axes[k].model.summary.temp_max_c << "] C)\n";
  s << " */\ntypedef struct {\n  int initialized;\n"
    << "  " << n.real << " prev_c[" << axes.size() << "];  /* causal dT/dt: previous temperature, deg C */\n"
    << "  " << n.real << " err_c[" << axes.size() << "];   /* T minus the first lag L, deg C */\n"
    << "  " << n.real << " diff_c[" << axes.size() << "];  /* L minus the second lag, deg C */\n"
    << "  " << n.real << " drift[" << axes.size() << "];   /* last drift subtracted, " << o.output_unit << " */\n"
    << "} " << n.p << "_state;\n\n";
  s << "void " << n.p << "_init(" << n.p << "_state *state);\n";
  s << "/* One sample: dt_s since the previous call (ignored on the first), the sensor temperature,\n"
       " * the measured rates; writes rate_out = rate_in - drift (rate_out may alias rate_in). */\n";
  s << "void " << n.p << "_step(" << n.p << "_state *state, " << n.real << " dt_s, " << n.real << " temp_c,\n"
    << "    const " << n.real << " *rate_in, " << n.real << " *rate_out);\n\n#endif\n";
  return s.str();
}

void EmitPrelude(std::ostringstream& s, const std::vector<AxisDriftModel>& axes, const Names& n, bool any_rate) {
  bool any_svr = false;
  for (const auto& a : axes) any_svr = any_svr || IsSvr(a.model);
  s << "/* " << n.p << ".c: generated by gyrocomp export --format c (see " << n.p << ".h). */\n";
  s << "#include \"" << n.p << ".h\"\n\n";
  if (any_svr)
    s << "#include <math.h>\n\n#ifdef " << n.P << "_USE_FLOAT\n#define " << n.P << "_EXP expf\n#else\n#define "
      << n.P << "_EXP exp\n#endif\n\n";
  if (!any_rate) return;
  // CausalRateStep of causal_drift.cc.
  s << "/* Causal dT/dt: two first-order lags (backward Euler), estimate (L - M) / tau, delay 2 tau. */\n";
  s << "static " << n.real << " " << n.p << "_rate_step(" << n.real << " *prev, " << n.real << " *err, " << n.real
    << " *diff, int initialized, " << n.real << " dt_s, " << n.real << " temp_c, " << n.real << " tau_s) {\n";
  s << "  " << n.real << " a, b, x;\n  if (!initialized) {\n    *prev = temp_c;\n    *err = " << n.R(0.0)
    << ";\n    *diff = " << n.R(0.0) << ";\n    return " << n.R(0.0) << ";\n  }\n";
  s << "  if (!(dt_s > " << n.R(0.0) << ")) return *diff / tau_s;\n"
    << "  b = tau_s / (tau_s + dt_s);\n  a = " << n.R(1.0) << " - b;\n"
    << "  x = (temp_c - *prev) + *err;  /* T_k - L_{k-1}, small numbers only */\n"
    << "  *prev = temp_c;\n  *err = b * x;\n  *diff = b * (*diff + a * x);\n"
    << "  /* D a / (b dt) = D / tau, unbiased by the rounding of a and b */\n"
    << "  return *diff * a / (b * dt_s);\n}\n\n";
}

void EmitStep(std::ostringstream& s, const std::vector<AxisDriftModel>& axes, const CExportOptions& o, const Names& n) {
  s << "void " << n.p << "_init(" << n.p << "_state *state) {\n  int a;\n  state->initialized = 0;\n"
    << "  for (a = 0; a < " << n.P << "_NUM_AXES; ++a) {\n    state->prev_c[a] = " << n.R(0.0)
    << ";\n    state->err_c[a] = " << n.R(0.0) << ";\n    state->diff_c[a] = " << n.R(0.0) << ";\n    state->drift[a] = " << n.R(0.0) << ";\n  }\n}\n\n";
  s << "void " << n.p << "_step(" << n.p << "_state *state, " << n.real << " dt_s, " << n.real << " temp_c,\n"
    << "    const " << n.real << " *rate_in, " << n.real << " *rate_out) {\n";
  s << "  " << n.real << " t, r;\n";
  bool any_rate = false;
  for (const auto& a : axes) any_rate = any_rate || UsesRate(a.model);
  if (!any_rate) s << "  (void)dt_s;\n";
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const DriftModel& m = axes[k].model;
    const DriftFitSummary& f = m.summary;
    s << "  /* axis " << k << ": " << axes[k].axis << " (" << DriftModelKindName(m.kind) << ", "
      << DriftInputSetName(m.inputs) << ") */\n";
    s << "  t = temp_c;\n  if (t < " << n.R(f.temp_min_c) << ") t = " << n.R(f.temp_min_c) << ";\n  else if (t > "
      << n.R(f.temp_max_c) << ") t = " << n.R(f.temp_max_c) << ";\n";
    if (UsesRate(m)) {
      const double tau = ResolvedCausalTau(o.causal, m.rate);
      s << "  r = " << n.p << "_rate_step(&state->prev_c[" << k << "], &state->err_c[" << k << "], &state->diff_c[" << k
        << "], state->initialized, dt_s, temp_c, " << n.R(tau) << ");  /* delay " << CausalRateDelay(tau) << " s */\n";
      s << "  if (r < " << n.R(f.dtemp_min_c_per_s) << ") r = " << n.R(f.dtemp_min_c_per_s) << ";\n  else if (r > "
        << n.R(f.dtemp_max_c_per_s) << ") r = " << n.R(f.dtemp_max_c_per_s) << ";\n";
    } else {
      s << "  r = " << n.R(0.0) << ";\n";
    }
    s << "  state->drift[" << k << "] = " << n.R(o.output_scale) << " * " << n.p << "_a" << k << "_eval(t, r);\n";
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
  return causal.IsValid(error);
}

Result<GeneratedC> GenerateCEvaluator(const std::vector<AxisDriftModel>& axes, const CExportOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) return InvalidArgument(why);
  if (axes.empty()) return InvalidArgument("C export: no axis model given");
  bool any_rate = false;
  for (const auto& a : axes) {
    if (Status st = CheckFinite(a); !st.ok()) return st.error();
    any_rate = any_rate || UsesRate(a.model);
  }
  Names n;
  n.p = o.prefix;
  for (char c : o.prefix) n.P += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  n.real = n.p + "_real";
  GeneratedC out;
  out.header_name = n.p + ".h";
  out.source_name = n.p + ".c";
  out.header = Header(axes, o, n);
  std::ostringstream s;
  EmitPrelude(s, axes, n, any_rate);
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const DriftModel& m = axes[k].model;
    if (const PolynomialModel* p = m.structured ? &*m.structured : nullptr)
      EmitPolynomial(s, n, static_cast<int>(k), *p, UsesRate(m));
    else
      EmitSvr(s, n, static_cast<int>(k), *m.kernel);
  }
  EmitStep(s, axes, o, n);
  out.source = s.str();
  return out;
}

}  // namespace gyrocomp
