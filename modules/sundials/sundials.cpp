// CVODE and ARKODE-ERKStep behind rocking::ode::Integrator. The shared driver
// (SundialsIntegrator) owns the context and vectors, maps stop times,
// roots and failures; each backend supplies the few calls that differ.
module;
#include <rocking/eigen.hpp>
#include <cvode/cvode.h>
#include <arkode/arkode_erkstep.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <vector>
#include <fmt/format.h>
module rocking.sundials;
import rocking.errors;

namespace rocking::ode {

namespace {

using Map = Eigen::Map<Eigen::VectorXd>;
constexpr double eps = std::numeric_limits<double>::epsilon();

struct ContextDeleter { void operator()(SUNContext c) const { SUNContext_Free(&c); } };
struct VectorDeleter { void operator()(N_Vector v) const { N_VDestroy(v); } };
using Context = std::unique_ptr<std::remove_pointer_t<SUNContext>, ContextDeleter>;
using Vector = std::unique_ptr<std::remove_pointer_t<N_Vector>, VectorDeleter>;

Map view(N_Vector v) { return {N_VGetArrayPointer(v), N_VGetLength(v)}; }

class SundialsIntegrator : public Integrator {
 public:
  SundialsIntegrator(Eigen::Index n, Rhs rhs, Options o) : rhs_(std::move(rhs)), opt_(o) {
    SUNContext raw = nullptr;
    if (SUNContext_Create(nullptr, &raw) != 0) throw IntegrationError(IntegrationError::Kind::backend, 0, "SUNContext_Create");
    ctx_.reset(raw);
    y_nv_.reset(N_VNew_Serial(n, ctx_.get()));
    dky_nv_.reset(N_VNew_Serial(n, ctx_.get()));
    y_.setZero(n);
  }

  void reset(double t, const Eigen::VectorXd& y, Guards guards) override {
    if (!y.allFinite()) throw IntegrationError(IntegrationError::Kind::non_finite_state, t, "at the initial state");
    view(y_nv_.get()) = y;
    if (initialised_) add_counters();
    initialised_ ? backend_reinit(t) : backend_init(t);
    initialised_ = true;
    guards_ = std::move(guards);
    directions_.clear();
    for (Direction d : guards_.directions)
      directions_.push_back(d == Direction::rising ? 1 : d == Direction::falling ? -1 : 0);
    roots_.assign(directions_.size(), 0);
    check(backend_root_init(static_cast<int>(directions_.size())), t, "root init");
    if (!directions_.empty()) check(backend_root_direction(directions_.data()), t, "root direction");
    t_ = t_prev_ = restart_t_ = t;
    y_ = y;
  }

  void set_breakpoints(NextBreakpoint next) override { breakpoints_.set(std::move(next)); }

  StepReport step(double t_limit) override {
    if (t_ >= t_limit) return {Stop::limit, t_};
    const Stats s = stats();
    if (s.steps + s.rejected >= opt_.max_steps)
      throw IntegrationError(IntegrationError::Kind::max_steps, t_, std::to_string(opt_.max_steps) + " steps");
    const auto [bound, bp_ahead] = step_bound(breakpoints_, t_, t_limit);
    check(backend_stop_time(bound), t_, "stop time");
    double t_ret = t_;
    int flag = backend_one_step(bound, &t_ret);
    // A root within round-off of the restart is the event that caused the
    // restart, seen again from an interpolated state: not reported (as rk45).
    while (flag == root_return() && t_ret - restart_t_ <= 1000 * eps * std::max(1.0, std::abs(restart_t_)))
      flag = backend_one_step(bound, &t_ret);
    if (flag < 0) fail(flag);
    t_prev_ = t_;
    t_ = t_ret;
    y_ = view(y_nv_.get());
    if (flag == root_return()) {
      check(backend_root_info(roots_.data()), t_, "root info");
      const auto i = std::find_if(roots_.begin(), roots_.end(), [](int r) { return r != 0; }) - roots_.begin();
      ++events_;
      return {Stop::event, t_, static_cast<int>(i), roots_[static_cast<std::size_t>(i)] > 0 ? Direction::rising : Direction::falling};
    }
    if (flag == tstop_return()) {
      t_ = bound;  // exactly
      return {bp_ahead ? Stop::breakpoint : Stop::limit, t_};
    }
    return {Stop::step, t_};
  }

  double time() const override { return t_; }
  const Eigen::VectorXd& state() const override { return y_; }
  double previous_time() const override { return t_prev_; }
  void dense(double t, Eigen::Ref<Eigen::VectorXd> y) override {
    check(backend_dky(t, dky_nv_.get()), t, "dense output");
    y = view(dky_nv_.get());
  }
  Stats stats() const override {
    Stats s = base_;
    if (initialised_) backend_add_counters(s);  // a backend never started has counted nothing (and has no solver to ask)
    s.events = events_;
    return s;
  }

 protected:
  // SUNDIALS callbacks: the user pointer is this object.
  static int rhs_callback(double t, N_Vector y, N_Vector dydt, void* self) {
    auto* me = static_cast<SundialsIntegrator*>(self);
    Map out = view(dydt);
    me->rhs_(t, view(y), out);
    return out.allFinite() ? 0 : 1;  // 1: recoverable, the backend retreats
  }
  static int guard_callback(double t, N_Vector y, double* g, void* self) {
    auto* me = static_cast<SundialsIntegrator*>(self);
    Map out(g, static_cast<Eigen::Index>(me->directions_.size()));
    me->guards_.fn(t, view(y), out);
    return 0;
  }
  static void error_callback(int, const char*, const char* function, char* msg, void* self) {
    static_cast<SundialsIntegrator*>(self)->last_error_ = fmt::format("{}: {}", function, msg);
  }

  virtual void backend_init(double t) = 0;
  virtual void backend_reinit(double t) = 0;
  virtual int backend_root_init(int m) = 0;
  virtual int backend_root_direction(int* dirs) = 0;
  virtual int backend_root_info(int* roots) = 0;
  virtual int backend_stop_time(double t) = 0;
  virtual int backend_one_step(double t_out, double* t_ret) = 0;
  virtual int backend_dky(double t, N_Vector out) = 0;
  virtual void backend_add_counters(Stats& s) const = 0;
  virtual int root_return() const = 0;
  virtual int tstop_return() const = 0;
  virtual int too_much_work() const = 0;
  virtual std::vector<int> rhs_failures() const = 0;
  virtual std::string flag_name(int flag) const = 0;

  void check(int flag, double t, std::string_view what) const {
    if (flag < 0) throw IntegrationError(IntegrationError::Kind::backend, t, fmt::format("{} ({}) {}", what, flag_name(flag), last_error_));
  }
  [[noreturn]] void fail(int flag) const {
    const auto rhs_fail = rhs_failures();
    using K = IntegrationError::Kind;
    const K kind = flag == too_much_work() ? K::max_steps
                   : std::find(rhs_fail.begin(), rhs_fail.end(), flag) != rhs_fail.end() ? K::non_finite_state
                                                                                           : K::step_size_underflow;
    throw IntegrationError(kind, t_, fmt::format("{} {}", flag_name(flag), last_error_));
  }
  void add_counters() { backend_add_counters(base_); }  // ReInit zeroes the backend's counters

  Context ctx_;
  Vector y_nv_, dky_nv_;
  Rhs rhs_;
  Options opt_;

 private:
  Guards guards_;
  std::vector<int> directions_, roots_;
  Breakpoints breakpoints_;
  Eigen::VectorXd y_;
  double t_ = 0, t_prev_ = 0, restart_t_ = 0;
  bool initialised_ = false;
  long events_ = 0;
  Stats base_;
  std::string last_error_;
};

class Cvode final : public SundialsIntegrator {
 public:
  Cvode(Eigen::Index n, Rhs rhs, Options o) : SundialsIntegrator(n, std::move(rhs), o) {
    mem_ = CVodeCreate(CV_BDF, ctx_.get());
    if (mem_ == nullptr) throw IntegrationError(IntegrationError::Kind::backend, 0, "CVodeCreate");
    A_ = SUNDenseMatrix(n, n, ctx_.get());
    LS_ = SUNLinSol_Dense(y_nv_.get(), A_, ctx_.get());
  }
  ~Cvode() override {
    CVodeFree(&mem_);
    SUNLinSolFree(LS_);
    SUNMatDestroy(A_);
  }
  Cvode(const Cvode&) = delete;
  Cvode& operator=(const Cvode&) = delete;
  std::string name() const override { return "cvode"; }

 private:
  void backend_init(double t) override {
    check(CVodeInit(mem_, rhs_callback, t, y_nv_.get()), t, "CVodeInit");
    check(CVodeSetUserData(mem_, this), t, "user data");
    check(CVodeSetErrHandlerFn(mem_, error_callback, this), t, "error handler");
    check(CVodeSStolerances(mem_, opt_.rtol, opt_.atol), t, "tolerances");
    check(CVodeSetLinearSolver(mem_, LS_, A_), t, "linear solver");
    check(CVodeSetMaxNumSteps(mem_, -1), t, "max steps");  // the driver counts steps
    if (opt_.max_step < 1e300) check(CVodeSetMaxStep(mem_, opt_.max_step), t, "max step");
    if (opt_.initial_step > 0) check(CVodeSetInitStep(mem_, opt_.initial_step), t, "initial step");
  }
  void backend_reinit(double t) override { check(CVodeReInit(mem_, t, y_nv_.get()), t, "CVodeReInit"); }
  int backend_root_init(int m) override {
    const int flag = CVodeRootInit(mem_, m, m > 0 ? guard_callback : nullptr);
    return flag < 0 || m == 0 ? flag : CVodeSetNoInactiveRootWarn(mem_);
  }
  int backend_root_direction(int* dirs) override { return CVodeSetRootDirection(mem_, dirs); }
  int backend_root_info(int* roots) override { return CVodeGetRootInfo(mem_, roots); }
  int backend_stop_time(double t) override { return CVodeSetStopTime(mem_, t); }
  int backend_one_step(double t_out, double* t_ret) override { return CVode(mem_, t_out, y_nv_.get(), t_ret, CV_ONE_STEP); }
  int backend_dky(double t, N_Vector out) override { return CVodeGetDky(mem_, t, 0, out); }
  void backend_add_counters(Stats& s) const override {
    long nfe = 0, nfe_ls = 0, nst = 0, netf = 0, nncf = 0, nge = 0;
    CVodeGetNumRhsEvals(mem_, &nfe);
    CVodeGetNumLinRhsEvals(mem_, &nfe_ls);
    CVodeGetNumSteps(mem_, &nst);
    CVodeGetNumErrTestFails(mem_, &netf);
    CVodeGetNumNonlinSolvConvFails(mem_, &nncf);
    CVodeGetNumGEvals(mem_, &nge);
    s.rhs += nfe + nfe_ls;
    s.steps += nst;
    s.rejected += netf + nncf;
    s.guards += nge;
  }
  int root_return() const override { return CV_ROOT_RETURN; }
  int tstop_return() const override { return CV_TSTOP_RETURN; }
  int too_much_work() const override { return CV_TOO_MUCH_WORK; }
  std::vector<int> rhs_failures() const override { return {CV_RHSFUNC_FAIL, CV_REPTD_RHSFUNC_ERR, CV_UNREC_RHSFUNC_ERR, CV_FIRST_RHSFUNC_ERR}; }
  std::string flag_name(int flag) const override {
    char* name = CVodeGetReturnFlagName(flag);
    std::string out(name);
    free(name);
    return out;
  }

  void* mem_ = nullptr;
  SUNMatrix A_ = nullptr;
  SUNLinearSolver LS_ = nullptr;
};

class Arkode final : public SundialsIntegrator {
 public:
  using SundialsIntegrator::SundialsIntegrator;
  ~Arkode() override { ERKStepFree(&mem_); }
  Arkode(const Arkode&) = delete;
  Arkode& operator=(const Arkode&) = delete;
  std::string name() const override { return "arkode"; }

 private:
  void backend_init(double t) override {
    mem_ = ERKStepCreate(rhs_callback, t, y_nv_.get(), ctx_.get());
    if (mem_ == nullptr) throw IntegrationError(IntegrationError::Kind::backend, t, "ERKStepCreate");
    configure(t);
  }
  void configure(double t) {
    check(ERKStepSetUserData(mem_, this), t, "user data");
    check(ERKStepSetErrHandlerFn(mem_, error_callback, this), t, "error handler");
    check(ERKStepSStolerances(mem_, opt_.rtol, opt_.atol), t, "tolerances");
    check(ERKStepSetTableNum(mem_, ARKODE_DORMAND_PRINCE_7_4_5), t, "Dormand-Prince table");
    check(ERKStepSetMaxNumSteps(mem_, -1), t, "max steps");
    if (opt_.max_step < 1e300) check(ERKStepSetMaxStep(mem_, opt_.max_step), t, "max step");
    if (opt_.initial_step > 0) check(ERKStepSetInitStep(mem_, opt_.initial_step), t, "initial step");
  }
  void backend_reinit(double t) override { check(ERKStepReInit(mem_, rhs_callback, t, y_nv_.get()), t, "ERKStepReInit"); }
  int backend_root_init(int m) override {
    const int flag = ERKStepRootInit(mem_, m, m > 0 ? guard_callback : nullptr);
    return flag < 0 || m == 0 ? flag : ERKStepSetNoInactiveRootWarn(mem_);
  }
  int backend_root_direction(int* dirs) override { return ERKStepSetRootDirection(mem_, dirs); }
  int backend_root_info(int* roots) override { return ERKStepGetRootInfo(mem_, roots); }
  int backend_stop_time(double t) override { return ERKStepSetStopTime(mem_, t); }
  int backend_one_step(double t_out, double* t_ret) override { return ERKStepEvolve(mem_, t_out, y_nv_.get(), t_ret, ARK_ONE_STEP); }
  int backend_dky(double t, N_Vector out) override { return ERKStepGetDky(mem_, t, 0, out); }
  void backend_add_counters(Stats& s) const override {
    long nfe = 0, nst = 0, netf = 0, nge = 0;
    ERKStepGetNumRhsEvals(mem_, &nfe);
    ERKStepGetNumSteps(mem_, &nst);
    ERKStepGetNumErrTestFails(mem_, &netf);
    ERKStepGetNumGEvals(mem_, &nge);
    s.rhs += nfe;
    s.steps += nst;
    s.rejected += netf;
    s.guards += nge;
  }
  int root_return() const override { return ARK_ROOT_RETURN; }
  int tstop_return() const override { return ARK_TSTOP_RETURN; }
  int too_much_work() const override { return ARK_TOO_MUCH_WORK; }
  std::vector<int> rhs_failures() const override { return {ARK_RHSFUNC_FAIL, ARK_REPTD_RHSFUNC_ERR, ARK_UNREC_RHSFUNC_ERR, ARK_FIRST_RHSFUNC_ERR}; }
  std::string flag_name(int flag) const override {
    char* name = ERKStepGetReturnFlagName(flag);
    std::string out(name);
    free(name);
    return out;
  }

  void* mem_ = nullptr;
};

}  // namespace

Backend parse_backend(std::string_view name) {
  if (name == "rk45") return Backend::rk45;
  if (name == "cvode") return Backend::cvode;
  if (name == "arkode") return Backend::arkode;
  if (name == "rosw") return Backend::rosw;
  if (name == "auto") return Backend::automatic;
  throw InputError(
      fmt::format("--integrator {}: unknown integrator (choose auto, rk45, rosw, cvode or arkode)", name));
}

std::string_view backend_name(Backend b) {
  switch (b) {
    case Backend::rk45: return "rk45";
    case Backend::cvode: return "cvode";
    case Backend::arkode: return "arkode";
    case Backend::rosw: return "rosw";
    case Backend::automatic: return "auto";
  }
  return "rk45";
}

std::unique_ptr<Integrator> make_cvode(Eigen::Index n, Rhs rhs, Options o) {
  return std::make_unique<Cvode>(n, std::move(rhs), o);
}
std::unique_ptr<Integrator> make_arkode(Eigen::Index n, Rhs rhs, Options o) {
  return std::make_unique<Arkode>(n, std::move(rhs), o);
}
std::unique_ptr<Integrator> make_integrator(Backend b, Eigen::Index n, Rhs rhs, Options o, LinearSolve stiff) {
  switch (b) {
    case Backend::cvode: return make_cvode(n, std::move(rhs), o);
    case Backend::arkode: return make_arkode(n, std::move(rhs), o);
    case Backend::rosw: return make_rosenbrock_w(n, std::move(rhs), std::move(stiff), o);
    case Backend::rk45:
    case Backend::automatic: break;
  }
  return make_rk45(n, std::move(rhs), o);
}

}  // namespace rocking::ode
