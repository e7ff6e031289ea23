// Speed of the impact simulator and the contact-law fit.
//   build/bench/dynamics_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only
#include <vector>

#include <benchmark/benchmark.h>

#include "dynamics/contact_fit.h"
#include "dynamics/impact_simulator.h"

namespace hoof::dynamics {
namespace {

ImpactSimulator Make(Surface surface, double mu, double rtol = 1e-8) {
  ContactParameters c = PaperContact(surface);
  c.mu = mu;
  SimulatorOptions o;
  o.relative_tolerance = rtol;
  return ImpactSimulator(SpecimenParameters{}, c, o);
}

// The paper's oblique reference impact: steel, 20 deg, 3.28 m/s, mu = 0.12, rtol 1e-8.
void BM_ObliqueImpact(benchmark::State& state) {
  const ImpactSimulator sim = Make(Surface::kSteel, 0.12);
  const ImpactConditions ic = ImpactConditions::Paper(3.28, 20.0);
  int steps = 0;
  for (auto _ : state) {
    ImpactResult r = sim.Simulate(ic);
    steps = r.steps;
    benchmark::DoNotOptimize(r);
  }
  state.counters["steps"] = steps;
}
BENCHMARK(BM_ObliqueImpact);

void BM_NormalImpact(benchmark::State& state) {
  const auto surface = static_cast<Surface>(state.range(0));
  const ImpactSimulator sim = Make(surface, 0.0);
  const ImpactConditions ic = ImpactConditions::Paper(3.0, 0.0);
  for (auto _ : state) benchmark::DoNotOptimize(sim.Simulate(ic));
}
BENCHMARK(BM_NormalImpact)->Arg(0)->Arg(1)->Arg(2);

// Stick and slip: 5 deg, mu = 0.35 (sticks early, slips at the end).
void BM_StickImpact(benchmark::State& state) {
  const ImpactSimulator sim = Make(Surface::kSteel, 0.35);
  const ImpactConditions ic = ImpactConditions::Paper(3.0, 5.0);
  for (auto _ : state) benchmark::DoNotOptimize(sim.Simulate(ic));
}
BENCHMARK(BM_StickImpact);

// The same impact with an effect of ContactExtensions on, which runs the general equations
// (Hunt-Crossley damping; 6 states) or the tangential spring (7 states). Discovery fits these.
// With `made_each_time`, the simulator is made (and so validated) for every simulation, as
// discovery's fits make it (src/discovery/workspace.cc, Workspace::Predict).
void ObliqueImpactWith(benchmark::State& state, const ContactExtensions& extensions,
                       bool made_each_time = false) {
  ContactParameters c = PaperContact(Surface::kSteel);
  c.mu = 0.12;
  c.extensions = extensions;
  const ImpactSimulator sim(SpecimenParameters{}, c);
  const ImpactConditions ic = ImpactConditions::Paper(3.28, 20.0);
  if (made_each_time) {
    for (auto _ : state)
      benchmark::DoNotOptimize(ImpactSimulator(SpecimenParameters{}, c).Simulate(ic));
  } else {
    for (auto _ : state) benchmark::DoNotOptimize(sim.Simulate(ic));
  }
}
void BM_ObliqueImpactHuntCrossley(benchmark::State& state) {
  ContactExtensions e;
  e.hunt_crossley_N_s_m2 = 2e7;
  ObliqueImpactWith(state, e);
}
BENCHMARK(BM_ObliqueImpactHuntCrossley);
void BM_ObliqueImpactTangentialCompliance(benchmark::State& state) {
  ContactExtensions e;
  e.tangential_compliance_ratio = 1.0;
  ObliqueImpactWith(state, e);
}
BENCHMARK(BM_ObliqueImpactTangentialCompliance);

// The spring at the size the discovery scorecard hides (k/k_t = 0.02): a stiff tangential
// spring rings about 7 times faster than the normal contact, and sets the step.
void BM_ObliqueImpactStiffTangentialSpring(benchmark::State& state) {
  ContactExtensions e;
  e.tangential_compliance_ratio = 0.02;
  ObliqueImpactWith(state, e);
}
BENCHMARK(BM_ObliqueImpactStiffTangentialSpring);

// The Hunt-Crossley impact above with the simulator made for every simulation.
void BM_ObliqueImpactMadeEachTime(benchmark::State& state) {
  ContactExtensions e;
  e.hunt_crossley_N_s_m2 = 2e7;
  ObliqueImpactWith(state, e, true);
}
BENCHMARK(BM_ObliqueImpactMadeEachTime);

// A trial's worth of samples: 60 frame times around the impact.
void BM_ObliqueImpactAtFrameTimes(benchmark::State& state) {
  const ImpactSimulator sim = Make(Surface::kSteel, 0.12);
  const ImpactConditions ic = ImpactConditions::Paper(3.28, 20.0);
  std::vector<double> t;
  for (int i = -30; i < 30; ++i) t.push_back((i + 0.5) / 8000.0);
  for (auto _ : state) benchmark::DoNotOptimize(sim.Simulate(ic, t));
}
BENCHMARK(BM_ObliqueImpactAtFrameTimes);

// Fitting zeta to 12 normal impacts, with a 9-point valley and no objective map.
void BM_FitZeta(benchmark::State& state) {
  const SpecimenParameters specimen;
  const ImpactSimulator sim = Make(Surface::kConcrete, 0.0);
  std::vector<NormalImpact> impacts;
  for (int i = 0; i < 12; ++i) {
    const double v = 1.5 + 2.5 * i / 11.0;
    impacts.push_back({v, sim.Simulate(ImpactConditions::Paper(v, 0.0)).at_separation.v_SC.y() *
                              (1 + 0.01 * ((i % 3) - 1))});
  }
  ContactFitOptions options;
  options.map_points_k = options.map_points_b = 0;
  for (auto _ : state) benchmark::DoNotOptimize(FitNormalContact(impacts, specimen, options));
}
BENCHMARK(BM_FitZeta)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hoof::dynamics

BENCHMARK_MAIN();
