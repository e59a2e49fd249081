// rocking.integrator: a generic initial-value-problem integrator with events
// and breakpoints; it knows nothing of rocking. y' = f(t, y), y in R^n.
//
// The project's own backend is Dormand-Prince 5(4) (Dormand & Prince 1980),
// FSAL, with the PI step-size controller, the mixed rtol/atol RMS error norm,
// the automatic initial step and the 4th-order continuous extension of Hairer,
// Norsett & Wanner, Solving ODEs I (2nd ed.), II.5-II.6 and their DOPRI5 code:
//   y(t0 + s h) = r1 + s (r2 + (1-s) (r3 + s (r4 + (1-s) r5)))
// Beside it, for stiff systems, the Rosenbrock-W method ROS34PW2 (Rang &
// Angermann 2005; rosenbrock.cpp), linearly implicit in a stiff part the
// caller solves with. Events are scalar guards g_i(t, y), each with a direction; a sign change is
// looked for on the dense output at interior points of every step (so a
// crossing and back inside one step is not missed when the samples see it) and
// located by the Illinois method with bisection fallback (GuardScanner, shared
// with the exact integrator below). Breakpoints are times the integrator lands
// on exactly and never steps across, asked for one at a time. Beside it,
// make_exact_linear steps z' = A z + b a(t), a(t) piecewise linear, exactly
// (linear.cpp). The SUNDIALS backends (module rocking.sundials) implement the
// same interface.
module;
#include <rocking/eigen.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>
export module rocking.integrator;
import rocking.errors;

export namespace rocking::ode {

using Rhs = std::function<void(double t, Eigen::Ref<const Eigen::VectorXd> y,
                               Eigen::Ref<Eigen::VectorXd> dydt)>;
using GuardValues = std::function<void(double t, Eigen::Ref<const Eigen::VectorXd> y,
                                       Eigen::Ref<Eigen::VectorXd> g)>;

// The first breakpoint strictly after t, or +infinity. A function rather than
// a list, so that a long record's samples are not copied into the integrator.
using NextBreakpoint = std::function<double(double t)>;
// The next-breakpoint function of a list of times (any order).
NextBreakpoint breakpoint_list(std::vector<double> times);

// An integrator's breakpoints: the function is asked again only when t has
// left the interval [t asked, breakpoint given) of the last answer (most
// steps end inside it, and a record's next sample costs a search).
class Breakpoints {
 public:
  void set(NextBreakpoint next);  // and forget the last answer
  double after(double t);         // the first breakpoint strictly after t
 private:
  NextBreakpoint next_;
  double asked_ = std::numeric_limits<double>::infinity();
  double answer_ = -std::numeric_limits<double>::infinity();
};

// Where a step from t towards t_limit must end at the latest: the next
// breakpoint when it comes before t_limit, else t_limit.
struct StepBound {
  double t;
  bool breakpoint;
};
StepBound step_bound(Breakpoints& breakpoints, double t, double t_limit);

// Which sign changes of a guard are events.
enum class Direction { rising, falling, either };

// The active guards: fn fills one value per direction. Empty: no events.
struct Guards {
  GuardValues fn;
  std::vector<Direction> directions;
};

struct Options {
  double rtol = 1e-6;
  double atol = 1e-9;
  double max_step = std::numeric_limits<double>::infinity();
  // Guard samples per step: ceil(h / sample_spacing), for rk45 at least 2
  // and at most 4, for the exact steps at least 1 and at most 16 (which then
  // are no longer than 16 spacings); infinity: always 4. A caller that knows
  // the fastest time scale of its guards sets it to a fraction of it, so that
  // steps are sampled as densely as that needs, no more.
  double sample_spacing = std::numeric_limits<double>::infinity();
  double initial_step = 0;        // 0: chosen automatically
  long max_steps = 10'000'000;    // accepted + rejected, over the integrator's life
  // The leading components the step-size control weighs (-1: all). The rest
  // are quadratures that nothing else depends on (running sums of work),
  // integrated with the same steps but not steering them. rk45 only: the
  // SUNDIALS backends weigh every component.
  long error_components = -1;
};

// Guard samples in a step of length h (Options::sample_spacing): 4 without a
// spacing, else ceil(h / spacing) between fewest and most (a step that is a
// whole number of spacings up to round-off takes that number).
int guard_samples(double h, double sample_spacing, int fewest, int most);

enum class Stop { step, event, breakpoint, limit };

// Why step() returned. For an event: which guard, and which way it crossed.
struct StepReport {
  Stop reason = Stop::step;
  double t = 0;
  int guard = -1;
  Direction crossing = Direction::either;
};

struct Stats {
  long rhs = 0;       // right-hand-side evaluations
  long steps = 0;     // accepted steps
  long rejected = 0;  // rejected step attempts (error test or non-finite)
  long events = 0;    // events reported
  long guards = 0;    // guard-function evaluations
};

// A failure with its context; a RunError, so the app exits with code 3.
class IntegrationError : public RunError {
 public:
  enum class Kind { step_size_underflow, max_steps, non_finite_state, backend };
  IntegrationError(Kind kind, double t, const std::string& detail);
  Kind kind() const { return kind_; }
  double time() const { return time_; }

 private:
  Kind kind_;
  double time_;
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  // (Re)start at (t, y) with these guards, e.g. after the caller changed the
  // state at an event. A guard exactly zero at t is silent until it leaves zero.
  virtual void reset(double t, const Eigen::VectorXd& y, Guards guards) = 0;
  // Times to land on exactly and never step across, asked for one at a time.
  virtual void set_breakpoints(NextBreakpoint next) = 0;
  // One step towards t_limit (never past it): returns at the end of an
  // internal step, at an event (state interpolated there), at a breakpoint,
  // or on reaching t_limit. Throws IntegrationError.
  virtual StepReport step(double t_limit) = 0;
  virtual double time() const = 0;
  virtual const Eigen::VectorXd& state() const = 0;
  // Dense output: the state at any t in [previous_time(), time()].
  virtual double previous_time() const = 0;
  virtual void dense(double t, Eigen::Ref<Eigen::VectorXd> y) = 0;
  // The state at sample k of `count` evenly spaced over the last step
  // (k = count is its end): dense output at sample_time(k, count), which an
  // integrator may serve from what it computed for its own guard samples.
  // Valid until the integrator is stepped or reset, or (by default) asked for
  // another sample: read it, do not keep it.
  virtual const Eigen::VectorXd& sample(int k, int count);
  double sample_time(int k, int count) const;
  // The same for a step from t0 to t1 (the one formula every caller uses).
  static double sample_time(double t0, double t1, int k, int count) {
    return k == count ? t1 : t0 + (t1 - t0) * k / count;
  }
  // How many samples of the last step its guards were scanned at (and a
  // caller's own sampling, e.g. of peaks, may take the same ones).
  virtual int sample_count() const { return 4; }
  virtual Stats stats() const = 0;
  virtual std::string name() const = 0;

 protected:
  Eigen::VectorXd sample_buffer_;  // what the default sample() returns
};

std::unique_ptr<Integrator> make_rk45(Eigen::Index n, Rhs rhs, Options options);

// x = (I - g T)^-1 b for a fixed matrix T (the stiff part of the Jacobian, or
// any approximation of it) and any g > 0.
using LinearSolve = std::function<void(double g, Eigen::Ref<const Eigen::VectorXd> b, Eigen::Ref<Eigen::VectorXd> x)>;
// The Rosenbrock-W method ROS34PW2 (rosenbrock.cpp): order 3 with any T,
// L-stable, so that a stiff system whose stiff part T captures is stepped at
// the accuracy's pace; events, breakpoints and dense output (order 2) as
// rk45. An empty solve means T = 0 (an explicit method of order 3, its dense
// output the cubic Hermite interpolant, of order 3).
std::unique_ptr<Integrator> make_rosenbrock_w(Eigen::Index n, Rhs rhs, LinearSolve solve, Options options);

// y' = f(t, y) where, on the block z = y[first, first + m), f = A z + b a(t),
// and every other component of y is constant; a(t) is linear between
// breakpoints (the caller lists every kink of a as a breakpoint). A must be
// diagonalisable and invertible (a damped structure on a fixed base is).
struct LinearSystem {
  Eigen::Index size = 0, first = 0;
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  std::function<double(double)> forcing;
  // Integrals carried alongside (the work of a linear phase's forces): the
  // component `at` of y, outside z, grows at z' Q z + a(t) c' z, integrated in
  // closed form. They are exact at every step's end and at a located event;
  // dense output and guard samples hold their values at the step's start.
  struct Quadrature {
    Eigen::Index at = 0;
    Eigen::MatrixXd Q;  // symmetric; empty: no quadratic term
    Eigen::VectorXd c;  // empty: no input term
  };
  std::vector<Quadrature> quadratures;
};
// Exact steps of y' = A z + b a(t) (see linear.cpp); a step ends at a
// breakpoint or after Options::max_step, which sets how densely the guards are
// sampled. Tolerances are not used: there is no truncation error to control.
std::unique_ptr<Integrator> make_exact_linear(LinearSystem system, Options options);

// For Integrator implementations: the guards' signs at the last sample, the
// scan of a step's samples for wanted sign changes, and their location on the
// dense output by the Illinois method with bisection fallback.
class GuardScanner {
 public:
  struct Crossing {
    double t;
    int guard;
    int to_sign;
    StepReport report() const {
      return {Stop::event, t, guard, to_sign > 0 ? Direction::rising : Direction::falling};
    }
  };

  // New guards at (t, y); a guard exactly zero there is silent until it leaves zero.
  void reset(Guards guards, double t, Eigen::Ref<const Eigen::VectorXd> y);
  // Samples k = 1..count of the step the integrator just took (its sample()):
  // the earliest wanted crossing, located to round-off on its dense output; a
  // crossing within round-off of the last restart (the event that caused it,
  // seen again) is not reported.
  bool scan(Integrator& stepped, int count, Crossing& found);
  // The state was moved to crossing c at time c.t: signs are taken there.
  void restart_at(const Crossing& c, Eigen::Ref<const Eigen::VectorXd> y);
  long evaluations() const { return evaluations_; }

 private:
  void evaluate(double t, Eigen::Ref<const Eigen::VectorXd> y, Eigen::VectorXd& g);
  double locate(Integrator& stepped, int i, double a, int sa, double ga, double b, double gb);

  Guards guards_;
  Eigen::VectorXd g_, g_work_, y_work_;
  std::vector<int> ref_sign_;
  std::vector<double> ref_time_, ref_value_;  // the last sample with a definite sign, and the value there
  double restart_t_ = 0;
  long evaluations_ = 0;
};

// Steps until t_end or the first event; returns the final report.
StepReport advance(Integrator& integrator, double t_end);

}  // namespace rocking::ode

// Not exported: what the adaptive one-step methods (rk45.cpp, rosenbrock.cpp)
// share, as a base that calls its method's hooks directly (no virtual call in
// the step loop). Method provides:
//   double attempt(double h)             trial step from (t_, y_): error norm, NaN if non-finite
//   void accept(double h, double t_new)  take it: y_, t_prev_, t_, h_dense_; ++stats_.steps
//   double next_step(double h, double err)   after an accepted step (its controller)
//   double retry_step(double h, double err)  after a rejected one
//   void derivative_at_state()           f(t_, y_) into its first stage (after an event)
// and dense(). The loop: steps end at the bound (a breakpoint or t_limit,
// two equal steps rather than one and a stub), a non-finite trial retreats
// to a tenth, max_steps and step-size underflow throw; after each accepted
// step the guards are scanned at guard_samples(h, sample_spacing, 2, 4)
// samples of its dense output.
namespace rocking::ode::detail {

inline constexpr int max_samples_per_step = 4;  // guard samples inside each step (incl. its end)

template <class Method>
class Adaptive : public Integrator {
 public:
  void set_breakpoints(NextBreakpoint next) override { breakpoints_.set(std::move(next)); }

  StepReport step(double t_limit) override {
    constexpr double eps = std::numeric_limits<double>::epsilon();
    if (t_ >= t_limit) return {Stop::limit, t_};
    const auto [bound, bp_ahead] = step_bound(breakpoints_, t_, t_limit);
    bool non_finite = false;
    for (;;) {
      if (stats_.steps + stats_.rejected >= opt_.max_steps)
        throw IntegrationError(IntegrationError::Kind::max_steps, t_, std::to_string(opt_.max_steps) + " steps");
      double h = std::min(h_, opt_.max_step);
      if (t_ + h < bound && t_ + 2 * h > bound) h = 0.5 * (bound - t_);  // two equal steps, not one and a stub
      const bool lands = t_ + h >= bound - 16 * eps * std::abs(bound);
      if (lands) h = bound - t_;
      if (h <= 16 * eps * std::max(std::abs(t_), 1.0))
        throw IntegrationError(non_finite ? IntegrationError::Kind::non_finite_state
                                          : IntegrationError::Kind::step_size_underflow, t_, "");
      const double err = method().attempt(h);
      if (!std::isfinite(err)) {  // the rhs blew up inside the step: retreat
        non_finite = true;
        h_ = 0.1 * h;
        ++stats_.rejected;
        last_rejected_ = true;
        continue;
      }
      if (err <= 1.0) {
        method().accept(h, lands ? bound : t_ + h);
        samples_valid_ = false;
        double h_next = method().next_step(h, err);
        if (last_rejected_) h_next = std::min(h_next, h);
        if (!lands || h_next > h_) h_ = h_next;  // a short landing step does not shrink h
        last_rejected_ = false;
        if (const StepReport e = find_event(); e.reason == Stop::event) return e;
        if (lands) return {bp_ahead ? Stop::breakpoint : Stop::limit, t_};
        return {Stop::step, t_};
      }
      h_ = method().retry_step(h, err);
      ++stats_.rejected;
      last_rejected_ = true;
    }
  }

  double time() const override { return t_; }
  const Eigen::VectorXd& state() const override { return y_; }
  double previous_time() const override { return t_prev_; }
  // The step's interior samples, computed once for the guards and the caller.
  const Eigen::VectorXd& sample(int k, int count) override {
    if (count != sample_count_ || k == count) return Integrator::sample(k, count);
    if (!samples_valid_) {
      for (int j = 1; j < count; ++j) dense(sample_time(j, count), samples_[j - 1]);
      samples_valid_ = true;
    }
    return samples_[k - 1];
  }
  int sample_count() const override { return sample_count_; }
  Stats stats() const override {
    Stats out = stats_;
    out.guards = scanner_.evaluations();
    return out;
  }

 protected:
  Adaptive(Eigen::Index n, Rhs rhs, Options o) : rhs_(std::move(rhs)), opt_(o) {
    y_.setZero(n);
    y_event_.setZero(n);
    for (auto& s : samples_) s.setZero(n);
  }

  // The common part of reset(): time, state and guards at (t, y).
  void begin(double t, const Eigen::VectorXd& y, Guards guards) {
    t_ = t_prev_ = t;
    y_ = y;
    scanner_.reset(std::move(guards), t, y_);
    last_rejected_ = false;
    samples_valid_ = false;
  }

  void rhs(double t, const Eigen::VectorXd& y, Eigen::VectorXd& f) {
    rhs_(t, y, f);
    ++stats_.rhs;
  }

  // The components the error norm weighs (Options::error_components).
  long controlled() const {
    return opt_.error_components < 0 ? static_cast<long>(y_.size())
                                     : std::min(static_cast<long>(y_.size()), opt_.error_components);
  }
  // v over the mixed tolerance of a component that is ya and yb at the step's ends.
  double scaled(double v, double ya, double yb) const {
    return v / (opt_.atol + opt_.rtol * std::max(std::abs(ya), std::abs(yb)));
  }
  double weighted_rms(const Eigen::VectorXd& v, const Eigen::VectorXd& ya, const Eigen::VectorXd& yb) const {
    double sum = 0;
    const long nc = controlled();
    for (Eigen::Index i = 0; i < nc; ++i) {
      const double r = scaled(v[i], ya[i], yb[i]);
      sum += r * r;
    }
    return std::sqrt(sum / static_cast<double>(nc));
  }

  Rhs rhs_;
  Options opt_;
  GuardScanner scanner_;
  double t_ = 0, t_prev_ = 0, h_ = 0, h_dense_ = 0;
  bool last_rejected_ = false, samples_valid_ = false;
  Eigen::VectorXd y_;
  Breakpoints breakpoints_;
  Stats stats_;

 private:
  Method& method() { return static_cast<Method&>(*this); }

  // Scans the guards at sample_count_ points of the last step; moves the
  // state to the earliest wanted crossing.
  StepReport find_event() {
    sample_count_ = guard_samples(t_ - t_prev_, opt_.sample_spacing, 2, max_samples_per_step);
    GuardScanner::Crossing c{};
    if (!scanner_.scan(*this, sample_count_, c)) return {Stop::step, t_};
    dense(c.t, y_event_);
    t_ = c.t;
    y_ = y_event_;
    samples_valid_ = false;  // the step now ends at the event
    method().derivative_at_state();  // the step end's derivative belongs to the discarded part
    scanner_.restart_at(c, y_);
    ++stats_.events;
    return c.report();
  }

  int sample_count_ = max_samples_per_step;  // of the last step
  std::array<Eigen::VectorXd, max_samples_per_step - 1> samples_;  // the last step's interior samples
  Eigen::VectorXd y_event_;
};

}  // namespace rocking::ode::detail
