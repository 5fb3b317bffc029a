#include "report_builder.h"

#include "gyrocomp/report/applicability.h"

namespace gyrocomp::cli {

void MarkNotApplicable(const AllanResult& allan, std::optional<double> bandwidth_hz, nlohmann::json* terms) {
  if (const TermApplicability t = ArwApplicability(allan, bandwidth_hz); !t.applicable) {
    (*terms)["arw_deg_per_sqrt_h"] = nullptr;
    (*terms)["arw_not_applicable"] = t.reason;
  }
  if (const TermApplicability t = RrwApplicability(allan, bandwidth_hz); !t.applicable) {
    (*terms)["rrw_deg_per_h_per_sqrt_h"] = nullptr;
    (*terms)["rrw_not_applicable"] = t.reason;
  }
}

void MarkNotApplicable(const PipelineResult& r, nlohmann::json* j) {
  if (j->contains("before")) MarkNotApplicable(r.allan_before, r.fs_hz / 2.0, &(*j)["before"]);
  if (j->contains("after")) MarkNotApplicable(r.allan_after, ProcessedBandwidth(r), &(*j)["after"]);
}

}  // namespace gyrocomp::cli
