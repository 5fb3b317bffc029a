// gyrocomp entropy: sample entropy of one column of a CSV (method.md section 2).
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "commands.h"
#include "entropy_memory.h"
#include "gyrocomp/io/io.h"
#include "gyrocomp/decompose/sample_entropy.h"

namespace gyrocomp::cli {
namespace {

constexpr const char* kEntropyName = "entropy";

struct EntropyArgs {
  std::string input;
  std::string col;
  SampleEntropyOptions options;  // library defaults: m = 2, r = 0.2 SD
  std::optional<double> r_abs;
  bool brute_force = false;
  std::string json_path;
};

int Run(EntropyArgs a) {
  ReuseFreedMemory();
  if (a.r_abs) a.options.r_absolute = *a.r_abs;
  if (a.brute_force) a.options.algorithm = SampleEntropyAlgorithm::kBruteForce;
  std::string why;
  if (!a.options.IsValid(&why)) return ReportError(kEntropyName, InvalidArgument(why));
  CsvReadOptions read;
  read.columns = std::vector<std::string>{a.col};  // the one column used (memory)
  Result<Table> table = ReadCsv(a.input, read);
  if (!table.ok()) return ReportError(kEntropyName, table.error());
  const int j = table->Find(a.col);
  if (j < 0) {
    std::string names;
    for (const std::string& n : table->FileNames()) names += (names.empty() ? "" : ", ") + n;
    return ReportError(kEntropyName, InvalidInput(table->source + ":1: no column '" + a.col + "' (columns: " + names + ")"));
  }
  Result<SampleEntropyResult> r = SampleEntropy(table->columns[j], a.options);
  if (!r.ok()) return ReportError(kEntropyName, Error{r.error().kind, table->source + ": column '" + a.col + "': " + r.error().message});

  nlohmann::json out;
  // JSON has no infinity/NaN: null, with `defined` and the counts telling why.
  out["sample_entropy"] = std::isfinite(r->sample_entropy) ? nlohmann::json(r->sample_entropy) : nlohmann::json();
  out["m"] = r->m;
  out["r"] = r->r;
  out["n"] = r->n;
  out["r_factor"] = a.options.r_absolute ? nlohmann::json() : nlohmann::json(a.options.r_factor);
  out["defined"] = r->defined;
  out["a_matches"] = r->a_matches;
  out["b_matches"] = r->b_matches;
  out["algorithm"] = a.brute_force ? "brute-force" : "fast";
  out["seconds"] = r->elapsed_s;
  out["input"] = table->source;
  out["column"] = a.col;
  if (!a.json_path.empty()) {
    if (Status s = WriteJson(a.json_path, out); !s.ok()) return ReportError(kEntropyName, s.error());
  }
  if (a.json_path != "-") std::cout << a.col << ": " << r->BriefReport() << "\n";
  if (std::isinf(r->sample_entropy)) Note(kEntropyName, "no template match of length m+1: SampEn is infinite (JSON null)");
  if (!r->defined) Note(kEntropyName, "no template match of length m: SampEn is undefined (JSON null)");
  return kExitOk;
}

Command MakeEntropy(CLI::App& app) {
  auto args = std::make_shared<EntropyArgs>();
  CLI::App* sub = app.add_subcommand(kEntropyName, "Sample entropy of one column (Richman & Moorman 2000; method.md section 2)");
  sub->footer(
      "Definition: templates of length m and m+1 from the same N-m start points, Chebyshev distance,\n"
      "a match when the distance is < r (strict: quantized data has distances equal to r), no\n"
      "self-matches; SampEn = -ln(A/B). r = --r x the column's population SD, or --r-abs.\n"
      "Counting is exact and fast (range counting, O(N log^m N)): the same A and B as the O(N^2)\n"
      "definition (--brute-force), ties included.\n"
      "JSON: sample_entropy (null if infinite or undefined), m, r (the absolute tolerance used), n,\n"
      "  a_matches, b_matches, defined.\n"
      "Example: gyrocomp entropy -i log.csv --col rate_dps --m 2 --r 0.2 --json -");
  AddInputOption(sub, "-i,--input", &args->input, "Input CSV (header row; .gz read directly; '-' = stdin)")->required();
  sub->add_option("--col", args->col, "Column to measure")->required();
  sub->add_option("--m", args->options.m, "Embedding dimension m (1..10)")->capture_default_str();
  auto* r = sub->add_option("--r", args->options.r_factor, "Tolerance as a factor of the column's SD")->capture_default_str();
  auto* r_abs = sub->add_option("--r-abs", args->r_abs, "Absolute tolerance, in the column's unit");
  r->excludes(r_abs);
  sub->add_flag("--brute-force", args->brute_force, "Use the O(N^2) definition (for checking)");
  AddOutputOption(sub, "--json", &args->json_path, "Write the result as JSON to FILE ('-' = stdout)");
  return {sub, [args] { return Run(*args); }};
}

const CommandRegistrar kEntropyRegistrar(kEntropyName, 45, &MakeEntropy);

}  // namespace
}  // namespace gyrocomp::cli
