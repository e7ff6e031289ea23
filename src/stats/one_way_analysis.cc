#include "stats/one_way_analysis.h"

#include <sstream>
#include <stdexcept>

#include "stats/moments.h"

namespace hoof::stats {
namespace {

std::string ZeroVarianceGroup(const GroupedData& data) {
  const Moments m = ComputeMoments(data);
  for (std::size_t g = 0; g < data.groups(); ++g)
    if (!(m.groups[g].sum_sq > 0.0L)) return data.labels[g];
  return {};
}

OneWayScaleResults RunScale(const GroupedData& data, double alpha) {
  OneWayScaleResults s;
  s.anova = OneWayAnova(data);  // Throws on data no step can use.
  s.groups = Summarize(data);
  s.bartlett = Bartlett(data);
  const std::string zero = ZeroVarianceGroup(data);
  if (zero.empty()) {
    s.welch = WelchAnova(data);
  } else {
    s.welch_note = "not computed: group \"" + zero +
                   "\" has zero variance, so its Welch weight n/s^2 is infinite";
  }
  std::ostringstream os;
  os << "ANOVA p = " << s.anova.p << (s.anova.p < alpha ? " < " : " >= ") << "alpha = " << alpha;
  if (s.anova.p < alpha) {
    s.lsd_performed = true;
    s.lsd = FisherLsd(data, alpha);
  } else {
    s.lsd_note = "not performed: " + os.str();
  }
  return s;
}

}  // namespace

void OneWayAnalysisOptions::Validate() const {
  if (!(alpha > 0.0 && alpha < 1.0)) {
    std::ostringstream os;
    os << "alpha = " << alpha << " must be in (0, 1)";
    throw std::invalid_argument(os.str());
  }
  box_cox.Validate();
}

OneWayAnalysis AnalyzeOneWay(const GroupedData& data, const OneWayAnalysisOptions& options) {
  options.Validate();
  OneWayAnalysis a;
  a.alpha = options.alpha;
  a.original = RunScale(data, options.alpha);
  TransformDecision& t = a.transform;
  std::ostringstream os;
  os << "Bartlett p = " << a.original.bartlett.p;
  if (!(a.original.bartlett.p < options.alpha)) {
    os << " >= alpha = " << options.alpha << ": equal variances not rejected, no transform";
    t.reason = os.str();
    return a;
  }
  os << " < alpha = " << options.alpha << ": Box-Cox";
  t.considered = true;
  t.box_cox = EstimateBoxCox(data, options.box_cox);
  os << " lambda = " << t.box_cox->lambda << " (" << t.box_cox->rule << ")";
  if (t.box_cox->lambda == 1.0) {
    os << "; lambda = 1 is the identity, data left as they are";
    t.reason = os.str();
    return a;
  }
  t.applied = true;
  t.formula = DescribeBoxCox(t.box_cox->lambda, t.box_cox->shift);
  os << "; analysis rerun on " << t.formula;
  t.reason = os.str();
  t.rerun = RunScale(ApplyBoxCox(data, t.box_cox->lambda, t.box_cox->shift), options.alpha);
  return a;
}

}  // namespace hoof::stats
