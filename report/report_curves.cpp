// Time to quality in the `penumbra compare` report: the methods' curves averaged over seeds,
// when each reaches a given MSE, and the table of report.md (report.html's charts and table
// are in report_charts.cpp).
#include "report/report_detail.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace penumbra::report::detail {

const char* const kCurveTimingNote =
    "Each point is the image the method's user gets (reconstructed unless the entry is raw) "
    "against the reference, at checkpoints during the run: at times growing by a factor of "
    "√2 from 1/16 of the budget in an equal-time run, after the rounds whose kept spp reaches "
    "1, 2, 4, ... in an equal-spp run, and at the end. A point's time is the method's own wall "
    "time: the time spent measuring earlier checkpoints (their snapshots and metrics, and an "
    "equal-spp run's probe of its kept spp after each round) is left out, and an equal-time "
    "run's deadline is extended by it, so every method gets the same time for its own work; "
    "the checkpoint's own snapshot (its reconstruction) counts, as it is part of what that "
    "image costs.";

bool anyCurve(const CompareReport& r) {
  for (const MethodResult& m : r.methods)
    for (const MethodRun& run : m.runs)
      if (!run.curve.empty()) return true;
  return false;
}

std::vector<CurvePoint> meanCurve(const MethodResult& m) {
  std::vector<const std::vector<CurvePoint>*> curves;
  for (const MethodRun& run : m.runs)
    if (!run.curve.empty()) curves.push_back(&run.curve);
  std::vector<CurvePoint> mean;
  if (curves.empty()) return mean;
  const auto find = [](const std::vector<CurvePoint>& curve, int checkpoint) -> const CurvePoint* {
    for (const CurvePoint& point : curve)
      if (point.checkpoint == checkpoint) return &point;
    return nullptr;
  };
  for (const CurvePoint& first : *curves[0]) {
    if (find(*curves[0], first.checkpoint) != &first) continue;  // a repeated checkpoint
    CurvePoint sum;
    sum.checkpoint = first.checkpoint;
    bool everySeed = true;
    for (const auto* curve : curves) {
      const CurvePoint* point = find(*curve, first.checkpoint);
      if (!point) {
        everySeed = false;
        break;
      }
      sum.seconds += point->seconds;
      sum.mse += point->mse;
      sum.relMse += point->relMse;
      sum.toneMappedMse += point->toneMappedMse;
      sum.keptSpp += point->keptSpp;
    }
    if (!everySeed) continue;
    const double n = double(curves.size());
    sum.seconds /= n, sum.mse /= n, sum.relMse /= n, sum.toneMappedMse /= n, sum.keptSpp /= n;
    mean.push_back(sum);
  }
  std::stable_sort(mean.begin(), mean.end(),
                   [](const CurvePoint& a, const CurvePoint& b) { return a.seconds < b.seconds; });
  return mean;
}

Reach timeToReach(const std::vector<CurvePoint>& curve, double mse) {
  Reach reach;
  if (!(mse >= 0)) return reach;
  for (size_t i = 0; i < curve.size(); ++i) {
    const CurvePoint& b = curve[i];
    if (!(b.mse <= mse)) continue;
    if (i == 0) return {b.seconds, true};
    const CurvePoint& a = curve[i - 1];
    reach.seconds = b.seconds;
    // Log-log interpolation where every value is positive and the MSE fell.
    if (a.seconds > 0 && b.seconds > a.seconds && mse > 0 && b.mse > 0 && a.mse > b.mse) {
      const double t = (std::log(a.mse) - std::log(mse)) / (std::log(a.mse) - std::log(b.mse));
      reach.seconds =
          std::exp(std::log(a.seconds) + t * (std::log(b.seconds) - std::log(a.seconds)));
    }
    return reach;
  }
  return reach;
}

std::string reachText(const Reach& reach) {
  if (std::isnan(reach.seconds)) return "never";
  const std::string text = seconds(Stat{reach.seconds, 0, 1});
  return reach.atFirst ? "≤ " + text : text;
}

std::string curvesMarkdown(const Prepared& p) {
  const CompareReport& r = p.r;
  if (!anyCurve(r)) return "";
  std::string md =
      "## Time to quality\n\nWhen each method (row) first reaches the final mean MSE of each "
      "method (column), on its curve averaged over seeds (interpolated log-log between "
      "checkpoints; ≤: already at the first checkpoint; never: not within the run). Every "
      "point is in curves.csv.\n\n| method | final time |";
  std::string rule = "\n|---|--:|";
  for (size_t c = 0; c < r.methods.size(); ++c) {
    const std::vector<CurvePoint>& target = p.meanCurves[c];
    md += ' ';
    md += markdownCell(r.methods[c].label) + "'s MSE " +
          (target.empty() ? std::string("n/a") : sci(target.back().mse)) + " |";
    rule += "--:|";
  }
  md += rule + "\n";
  for (size_t m = 0; m < r.methods.size(); ++m) {
    const std::vector<CurvePoint>& curve = p.meanCurves[m];
    md += "| ";
    md += markdownCell(r.methods[m].label) + " | " +
          (curve.empty() ? std::string("n/a") : seconds(Stat{curve.back().seconds, 0, 1})) + " |";
    for (size_t c = 0; c < r.methods.size(); ++c) {
      const std::vector<CurvePoint>& target = p.meanCurves[c];
      md += ' ';
      md += curve.empty() || target.empty() ? std::string("n/a")
                                            : reachText(timeToReach(curve, target.back().mse));
      md += " |";
    }
    md += "\n";
  }
  return md + "\n" + kCurveTimingNote + "\n\n";
}

}  // namespace penumbra::report::detail
