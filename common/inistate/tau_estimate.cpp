#include "inistate/tau_estimate.h"

#include <omp.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <memory>
#include <sstream>

#include "core/atomic_file.h"
#include "core/cancel.h"
#include "core/error.h"
#include "core/log.h"
#include "inistate/inistate_planner.h"
#include "planning/path_io.h"

namespace ausbau {

void TauEstimateOptions::Check() const {
  if (!(initial_speed > 0) || !std::isfinite(initial_speed))
    throw OptionError(&initial_speed, "initial_speed", "must be > 0");
  if (!(speed_step >= 0) || !std::isfinite(speed_step)) throw OptionError(&speed_step, "speed_step", "must be >= 0");
  if (max_rounds < 1 || max_rounds > 100) throw OptionError(&max_rounds, "rounds", "must lie in [1, 100]");
  if (probe_attempts < 10 || probe_attempts > 1000000)
    throw OptionError(&probe_attempts, "probe_attempts", "must lie in [10, 10^6]");
  if (bisection_steps < 0 || bisection_steps > 30)
    throw OptionError(&bisection_steps, "bisection_steps", "must lie in [0, 30]");
  if (!(max_tau >= 0) || !std::isfinite(max_tau)) throw OptionError(&max_tau, "max_tau", "must be >= 0");
  if (threads < 0) throw OptionError(&threads, "threads", "must be >= 0");
  if (round_checks < 1) throw OptionError(&round_checks, "round_checks", "must be >= 1");
  planner.Check();
}

namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point begin) { return std::chrono::duration<double>(Clock::now() - begin).count(); }

TauProbe RunProbe(const PlanningProblem& problem, const IntersectionVolume& volume, VolumeMeasure measure, double tau,
                  double psi, const TauEstimateOptions& options, const std::atomic<bool>* cancel = nullptr) {
  const auto begin = Clock::now();
  const VolumeValidity validity(volume, measure, tau);
  PlannerOptions probe = LocalPlannerOptions(problem, psi, options.planner);
  probe.max_iterations = options.probe_attempts;
  probe.time_limit_s = 1e6;  // the attempt budget ends a probe, never the clock (determinism)
  probe.cancel = cancel;
  probe.progress = nullptr;  // probes run on two threads; the rounds log lines instead
  const PlanResult result = Plan(problem, validity, probe);
  TauProbe out;
  out.tau = tau;
  out.nodes = result.stats.nodes;
  out.attempts = result.stats.iterations;
  out.checks = result.stats.collision_checks;
  if (result.solved()) {
    out.speed = std::numeric_limits<double>::infinity();
  } else {
    const double reference_seconds = std::max<double>(1, out.checks) / kChecksPerReferenceSecond;
    out.speed = static_cast<double>(std::max<std::int64_t>(0, out.nodes - 1)) / reference_seconds;
  }
  out.seconds = Seconds(begin);
  return out;
}

std::string Describe(const TauProbe& p) {
  char line[200];
  std::snprintf(line, sizeof line, "tau %.6g: %lld nodes in %lld attempts, %lld checks -> %s nodes/s", p.tau,
                static_cast<long long>(p.nodes), static_cast<long long>(p.attempts), static_cast<long long>(p.checks),
                std::isinf(p.speed) ? "goal reached" : std::to_string(p.speed).c_str());
  return line;
}

// The search of EstimateTau: rounds of (a tau search by speed probes, then a
// planning round at that tau), with raised speed targets after each failed
// round. The lambdas of one 220-line function became these methods; the
// state they share is the members.
class TauSearch {
 public:
  TauSearch(const PlanningProblem& problem, const IntersectionVolume& volume, VolumeMeasure measure, double psi,
            const TauEstimateOptions& options)
      : problem_(problem), volume_(volume), measure_(measure), psi_(psi), options_(options) {}

  TauEstimate Run();

 private:
  // One round's tau search ends with a tau, with none reaching the target,
  // or cancelled (the second lane, when the first round succeeded).
  enum class Search { kFound, kExhausted, kCancelled };

  // The search state that carries from one round to the next. A round's tau
  // depends only on the probes and on the rounds before it having failed, so
  // the taus of later rounds can be found before the earlier rounds are
  // planned (Run: the two lanes).
  struct SearchState {
    int k_pass = 0;     // candidates below this index are known to be too slow for the previous target
    double lower = -1;  // largest tau known too slow for the current target
    double floor = -1;  // after a failed round: the next tau is at least this
  };

  struct Round {
    int index = 0;
    double target = 0, tau = 0;
    std::vector<TauProbe> probes;
    std::vector<std::string> lines;
    Search search = Search::kCancelled;
    bool planned = false;
    PlanResult result;
    double seconds = 0;
  };

  void Say(const std::string& line) const { LogInfo("%s", line.c_str()); }
  double Candidate(int k) const { return estimate_.tau_lowest + delta_ * (std::ldexp(1.0, k) - 1.0); }
  Search FindRoundTau(int round, double target, std::vector<TauProbe>* round_trace, std::vector<std::string>* lines,
                      double* tau_out, const std::atomic<bool>* cancel);
  void AssumeFailed(double failed_tau);
  void PlanRound(Round* round, const std::atomic<bool>* cancel) const;
  bool Accept(Round& round);
  Round NewRound(int index) const {
    Round round;
    round.index = index;
    round.target = options_.initial_speed + index * options_.speed_step;
    return round;
  }
  void SearchRound(Round* round, const std::atomic<bool>* cancel) {
    round->search = FindRoundTau(round->index, round->target, &round->probes, &round->lines, &round->tau, cancel);
  }

  const PlanningProblem& problem_;
  const IntersectionVolume& volume_;
  const VolumeMeasure measure_;
  const double psi_;
  const TauEstimateOptions& options_;
  TauEstimate estimate_;
  double delta_ = 0, max_tau_ = 0;
  int threads_ = 1;
  SearchState state_;
};

// One round's tau search; its probes (and log lines) go to `round_trace`
// and `lines`. A raised `cancel` ends it early (kCancelled).
TauSearch::Search TauSearch::FindRoundTau(int round, double target, std::vector<TauProbe>* round_trace,
                                          std::vector<std::string>* lines, double* tau_out,
                                          const std::atomic<bool>* cancel) {
  auto cancelled = [&] { return (cancel != nullptr && cancel->load()) || CancelRequested(); };
  auto record = [&](TauProbe probe) {
    probe.round = round;
    probe.target_speed = target;
    lines->push_back(Describe(probe));
    round_trace->push_back(probe);
  };
  // Doubling: probe candidates k_pass, k_pass + 1, ... in parallel batches.
  int found = -1;
  for (int k0 = state_.k_pass; found < 0; k0 += threads_) {
    if (Candidate(k0) > max_tau_) break;
    if (cancelled()) return Search::kCancelled;
    std::vector<TauProbe> batch(threads_);
    std::vector<std::uint8_t> valid(threads_, 0);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads_)
    for (int i = 0; i < threads_; ++i) {
      const double t = Candidate(k0 + i);
      if (t > max_tau_) continue;
      batch[i] = RunProbe(problem_, volume_, measure_, t, psi_, options_, cancel);
      valid[i] = 1;
    }
    for (int i = 0; i < threads_ && found < 0; ++i) {
      if (!valid[i]) continue;
      record(batch[i]);
      if (batch[i].speed >= target) {
        found = k0 + i;
      } else {
        state_.lower = batch[i].tau;
      }
    }
  }
  if (found < 0) {
    lines->push_back("no tau up to " + std::to_string(max_tau_) + " reaches " + std::to_string(target) + " nodes/s");
    return Search::kExhausted;
  }
  state_.k_pass = found;
  double upper = Candidate(found);
  double lower = state_.lower;
  if (lower < estimate_.tau_lowest || lower >= upper) lower = found > 0 ? Candidate(found - 1) : -1;
  // Bisection never goes below the floor a failed round set.
  if (state_.floor >= 0) lower = std::max(lower, std::min(state_.floor, upper));
  // Bisection between the last too-slow and the first fast-enough candidate.
  for (int step = 0; step < options_.bisection_steps && lower >= 0 && upper - lower > 0.5 * delta_; ++step) {
    if (cancelled()) return Search::kCancelled;
    const double middle = 0.5 * (lower + upper);
    TauProbe probe = RunProbe(problem_, volume_, measure_, middle, psi_, options_, cancel);
    (probe.speed >= target ? upper : lower) = middle;
    record(probe);
  }
  if (cancelled()) return Search::kCancelled;
  *tau_out = upper;
  return Search::kFound;
}

// What a failed round at `failed_tau` leaves for the next: the next round
// searches above it, since its speed may already exceed the raised target
// (on clips-ds5 the tree reaches any speed by turning in place near the
// start) and the same tau would fail again; at least twice the failed
// tau's distance from the start's volume (plus two voxels), so that a few
// rounds span the range geometrically.
void TauSearch::AssumeFailed(double failed_tau) {
  state_.floor = estimate_.tau_lowest + 2.0 * (failed_tau - estimate_.tau_lowest) + 2.0 * delta_;
  state_.lower = failed_tau;
  while (Candidate(state_.k_pass) < state_.floor) ++state_.k_pass;
}

void TauSearch::PlanRound(Round* round, const std::atomic<bool>* cancel) const {
  const auto round_begin = Clock::now();
  const VolumeValidity validity(volume_, measure_, round->tau);
  PlannerOptions planner = LocalPlannerOptions(problem_, psi_, options_.planner);
  planner.time_limit_s = LimitByDeadline(planner.time_limit_s, options_.deadline, 0.5, nullptr);
  planner.max_checks = options_.round_checks;  // the round's work budget
  planner.cancel = cancel;
  planner.progress = nullptr;  // rounds run on two threads; each logs its line instead
  round->result = Plan(problem_, validity, planner);
  round->seconds = Seconds(round_begin);
  round->planned = true;
}

// Adds a searched (and maybe planned) round to the estimate; true when it
// ends the search (sigma_1 found, or no tau reaches its target).
bool TauSearch::Accept(Round& round) {
  for (const std::string& line : round.lines) Say(line);
  estimate_.trace.insert(estimate_.trace.end(), round.probes.begin(), round.probes.end());
  estimate_.speed_target = round.target;
  if (round.search == Search::kExhausted) return true;
  TauProbe planning;
  planning.round = round.index;
  planning.target_speed = round.target;
  planning.tau = round.tau;
  planning.nodes = round.result.stats.nodes;
  planning.attempts = round.result.stats.iterations;
  planning.checks = round.result.stats.collision_checks;
  planning.planning_round = true;
  planning.solved = round.result.solved();
  planning.seconds = round.seconds;
  estimate_.trace.push_back(planning);
  if (round.result.status == PlanStatus::kTimeLimit) {
    estimate_.cut_short = true;
    Say("round " + std::to_string(round.index + 1) +
        " was cut short by its time limit (a safety net): the estimate "
        "is not the deterministic one");
  }
  estimate_.rounds = round.index + 1;
  estimate_.tau = round.tau;
  Say("round " + std::to_string(round.index + 1) + ": tau " + std::to_string(round.tau) + " (target " +
      std::to_string(round.target) + " nodes/s): " + (planning.solved ? "sigma_1 found" : "no path") + " in " +
      std::to_string(round.seconds) + " s");
  if (!planning.solved) return false;
  estimate_.solved = true;
  estimate_.local_path = round.result.path;
  estimate_.local_seed = options_.planner.seed;
  estimate_.local_planner = options_.planner.planner;
  return true;
}

// Planning rounds in two lanes. A planning round runs on one core (the
// local planner is sequential) and a failed one costs its whole time limit,
// while the next round's tau depends only on the probes and on this round
// having failed. So while lane 1 plans round r, lane 2 searches the tau of
// round r + 1 as if r had failed and plans it. The first round in order
// that finds sigma_1 is the answer, exactly as if the rounds ran one after
// the other; when round r succeeds, lane 2 is cancelled and its probes and
// round are left out of the trace. One thread: one lane.
TauEstimate TauSearch::Run() {
  const auto begin = Clock::now();
  estimate_.psi = psi_;
  {
    IntersectionVolume start_volume = volume_.Clone();
    estimate_.tau_lowest = start_volume.Measure(measure_, problem_.start);
  }
  delta_ = volume_.voxel_volume();
  max_tau_ = options_.max_tau > 0 ? options_.max_tau : volume_.voxel_count() * volume_.voxel_volume();
  threads_ = options_.threads > 0 ? options_.threads : omp_get_max_threads();
  Say("tau search: start volume " + std::to_string(estimate_.tau_lowest) + ", step " + std::to_string(delta_) +
      ", at most " + std::to_string(max_tau_));

  Round current = NewRound(0);
  SearchRound(&current, nullptr);
  while (true) {
    ThrowIfCancelled();
    if (current.search != Search::kFound) {
      Accept(current);  // no tau reaches the target
      break;
    }
    for (const std::string& line : current.lines) Say(line);
    current.lines.clear();
    AssumeFailed(current.tau);  // for the next round's search
    const bool last = current.index + 1 >= options_.max_rounds;
    Round next = NewRound(current.index + 1);
    std::atomic<bool> cancel_next{false};
    std::exception_ptr errors[2];
    const int lanes = threads_ > 1 && !last ? 2 : 1;
#pragma omp parallel for schedule(static, 1) num_threads(lanes)
    for (int lane = 0; lane < lanes; ++lane) {
      try {
        if (lane == 0) {
          PlanRound(&current, nullptr);
          if (current.result.solved()) cancel_next = true;
        } else {
          SearchRound(&next, &cancel_next);
          if (next.search == Search::kFound && !cancel_next) PlanRound(&next, &cancel_next);
        }
      } catch (...) {
        errors[lane] = std::current_exception();
        cancel_next = true;
      }
    }
    for (const std::exception_ptr& error : errors) {
      if (error) std::rethrow_exception(error);
    }
    ThrowIfCancelled();  // the planners stopped early: no answer (core/cancel.h)
    if (Accept(current) || last) break;
    if (SecondsLeft(options_.deadline) <= 0) {
      Say("time budget used up: no more rounds");
      estimate_.cut_short = true;
      break;
    }
    if (lanes == 1) {  // search the next round now
      SearchRound(&next, nullptr);
    } else if (next.planned && next.result.status != PlanStatus::kCancelled) {
      // Planned alongside: accept it as it is; the round after it is next.
      if (Accept(next) || next.index + 1 >= options_.max_rounds) break;
      AssumeFailed(next.tau);
      current = NewRound(next.index + 1);
      SearchRound(&current, nullptr);
      continue;
    }
    current = std::move(next);  // searched, not planned yet (or no tau reaches its target)
  }
  if (estimate_.rounds == 0) estimate_.tau = estimate_.tau_lowest;  // no round was planned
  estimate_.seconds = Seconds(begin);
  return estimate_;
}

}  // namespace

TauEstimate EstimateTau(const PlanningProblem& problem, const IntersectionVolume& volume, VolumeMeasure measure,
                        double psi, const TauEstimateOptions& options) {
  options.Check();
  return TauSearch(problem, volume, measure, psi, options).Run();
}

// ---------------------------------------------------------------- artifact

void WriteTauArtifact(const std::filesystem::path& file, const TauArtifact& tau, const Provenance& provenance) {
  const TauEstimate& e = tau.estimate;
  ArtifactWriter w(file, kTauSchema, kTauSchemaVersion, provenance);
  w.WriteDoubles("tau", {e.tau}, {});
  w.SetAttribute("tau", "units", tau.units + "^3");
  w.WriteDoubles("psi", {e.psi}, {});
  w.SetAttribute("psi", "units", tau.units);
  w.WriteDoubles("tau_lowest", {e.tau_lowest}, {});
  w.WriteDoubles("speed_target", {e.speed_target}, {});
  w.WriteInts("rounds", {e.rounds}, {});
  w.WriteInts("solved", {e.solved ? 1 : 0}, {});
  w.WriteDoubles("seconds", {e.seconds}, {});
  if (e.cut_short) w.WriteInts("cut_short", {1}, {});  // optional: absent = the deterministic estimate
  w.SetAttribute("", "validity", ValidityModeName(tau.validity));
  w.SetAttribute("", "units", tau.units);
  const std::size_t n = e.trace.size();
  std::vector<double> taus, speeds, seconds, targets;
  std::vector<std::int64_t> rounds, nodes, attempts, checks, planning, solved;
  for (const TauProbe& p : e.trace) {
    rounds.push_back(p.round);
    targets.push_back(p.target_speed);
    taus.push_back(p.tau);
    speeds.push_back(std::isinf(p.speed) ? -1.0 : p.speed);
    nodes.push_back(p.nodes);
    attempts.push_back(p.attempts);
    checks.push_back(p.checks);
    planning.push_back(p.planning_round ? 1 : 0);
    solved.push_back(p.solved ? 1 : 0);
    seconds.push_back(p.seconds);
  }
  w.WriteInts("trace/round", rounds, {n});
  w.WriteDoubles("trace/target_speed", targets, {n});
  w.WriteDoubles("trace/tau", taus, {n});
  w.WriteDoubles("trace/speed", speeds, {n});
  w.SetAttribute("trace/speed", "note", "nodes per reference second; -1 = the probe reached the goal");
  w.WriteInts("trace/nodes", nodes, {n});
  w.WriteInts("trace/attempts", attempts, {n});
  w.WriteInts("trace/checks", checks, {n});
  w.WriteInts("trace/planning_round", planning, {n});
  w.WriteInts("trace/solved", solved, {n});
  w.WriteDoubles("trace/seconds", seconds, {n});
  if (e.solved && !e.local_path.empty()) {
    // The successful round's sigma_1, so that ausbau-plan need not plan it
    // again (it re-checks it, see PlanInIState).
    WritePoseRows(w, "sigma_1", e.local_path);
    w.SetAttribute("sigma_1", "convention", std::string("planning (x_world = R(q) (x - reference point) + t)"));
    w.SetAttribute("sigma_1", "seed", static_cast<std::int64_t>(e.local_seed));
    w.SetAttribute("sigma_1", "planner", e.local_planner);
  }
  w.Commit();
}

TauArtifact ReadTauArtifact(const std::filesystem::path& file) {
  ArtifactReader r(file, kTauSchema, kTauSchemaVersion);
  TauArtifact out;
  TauEstimate& e = out.estimate;
  auto scalar = [&](const char* name) {
    const Array<double> a = r.ReadDoubles(name);
    if (a.data.size() != 1) throw InputErrorAt(file.string(), std::string("dataset '") + name + "' must be a scalar");
    return a.data[0];
  };
  e.tau = scalar("tau");
  e.psi = scalar("psi");
  e.tau_lowest = scalar("tau_lowest");
  e.speed_target = scalar("speed_target");
  e.seconds = scalar("seconds");
  auto int_scalar = [&](const char* name) {
    const Array<std::int64_t> a = r.ReadInts(name);
    if (a.data.size() != 1) throw InputErrorAt(file.string(), std::string("dataset '") + name + "' must be a scalar");
    return a.data[0];
  };
  const std::int64_t round_count = int_scalar("rounds");
  if (round_count < 0 || round_count > std::numeric_limits<int>::max()) {
    throw InputErrorAt(file.string(), "dataset 'rounds' is out of range (" + std::to_string(round_count) + ")");
  }
  e.rounds = static_cast<int>(round_count);
  e.solved = int_scalar("solved") != 0;
  e.cut_short = r.Has("cut_short") && int_scalar("cut_short") != 0;
  if (r.Has("sigma_1")) {
    e.local_path = ReadPoseRows(r, "sigma_1");
    e.local_seed = static_cast<std::uint64_t>(r.ReadIntAttribute("sigma_1", "seed"));
    e.local_planner = r.ReadStringAttribute("sigma_1", "planner");
  }
  out.validity = ParseValidityMode(r.ReadStringAttribute("", "validity"), file.string() + ": attribute 'validity'");
  out.units = r.ReadStringAttribute("", "units");
  if (!(e.tau >= 0) || !std::isfinite(e.tau) || !(e.psi > 0) || !std::isfinite(e.psi)) {
    throw InputErrorAt(file.string(), "tau must be >= 0 and psi > 0");
  }
  const Array<double> taus = r.ReadDoubles("trace/tau", 1), speeds = r.ReadDoubles("trace/speed", 1),
                      targets = r.ReadDoubles("trace/target_speed", 1), seconds = r.ReadDoubles("trace/seconds", 1);
  const Array<std::int64_t> rounds = r.ReadInts("trace/round", 1), nodes = r.ReadInts("trace/nodes", 1),
                            attempts = r.ReadInts("trace/attempts", 1), checks = r.ReadInts("trace/checks", 1),
                            planning = r.ReadInts("trace/planning_round", 1), solved = r.ReadInts("trace/solved", 1);
  const std::size_t n = taus.data.size();
  for (const std::size_t size :
       {speeds.data.size(), targets.data.size(), seconds.data.size(), rounds.data.size(), nodes.data.size(),
        attempts.data.size(), checks.data.size(), planning.data.size(), solved.data.size()}) {
    if (size != n) throw InputErrorAt(file.string(), "trace datasets differ in length");
  }
  for (const Array<double>* values : {&taus, &speeds, &targets, &seconds}) {
    for (double v : values->data) {
      if (!std::isfinite(v)) throw InputErrorAt(file.string(), "trace datasets hold a non-finite value");
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    TauProbe p;
    p.round = static_cast<int>(rounds.data[i]);
    p.target_speed = targets.data[i];
    p.tau = taus.data[i];
    p.speed = speeds.data[i] < 0 ? std::numeric_limits<double>::infinity() : speeds.data[i];
    p.nodes = nodes.data[i];
    p.attempts = attempts.data[i];
    p.checks = checks.data[i];
    p.planning_round = planning.data[i] != 0;
    p.solved = solved.data[i] != 0;
    p.seconds = seconds.data[i];
    e.trace.push_back(p);
  }
  return out;
}

void WriteTauTraceCsv(const std::filesystem::path& file, const TauEstimate& estimate) {
  std::ostringstream out;
  out.precision(10);
  out << "round,target_speed,tau,speed,nodes,attempts,checks,planning_round,solved,seconds\n";
  for (const TauProbe& p : estimate.trace) {
    out << p.round << ',' << p.target_speed << ',' << p.tau << ',' << (std::isinf(p.speed) ? -1.0 : p.speed) << ','
        << p.nodes << ',' << p.attempts << ',' << p.checks << ',' << (p.planning_round ? 1 : 0) << ','
        << (p.solved ? 1 : 0) << ',' << p.seconds << '\n';
  }
  WriteTextFileAtomically(file, out.str());
}

}  // namespace ausbau
