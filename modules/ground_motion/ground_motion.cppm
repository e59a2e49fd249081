// rocking.ground_motion: the horizontal ground acceleration a_g(t) [m/s^2]
// (MODEL.md 10). A record is piecewise linear between its samples, which are
// breakpoints for the integrator; it is zero before its first and after its
// last sample. Readers: PEER .AT2 (the three header styles of
// shared/data/records/SOURCES.md: the line holding NPTS and DT, then every
// number after it; CRLF or LF; NPTS checked against the count), two-column
// (time, acceleration) and one-column (acceleration, with dt given) text.
// Units g, m/s2 or cm/s2 (g = 9.81 m/s^2, as in rocking.modal). Analytic pulses
// for tests, teaching and the default excitation:
//   one-sine: a(t) = A sin(2 pi t / T) on [0, T] (Makris & Roussos 2000),
//   Ricker:   a(t) = A (1 - 2 u) exp(-u), u = (pi f (t - t0))^2, t0 = 1.5 / f.
// Every reader error is an InputError of one line: file:line and what is wrong.
module;
#include <string>
#include <string_view>
#include <vector>
export module rocking.ground_motion;

export namespace rocking {

enum class AccelerationUnit { g, m_per_s2, cm_per_s2 };
// "g", "m/s2", "cm/s2"; InputError otherwise.
AccelerationUnit parse_acceleration_unit(std::string_view text);
double to_si(AccelerationUnit unit);  // factor to m/s^2

enum class PulseShape { one_sine, ricker };
PulseShape parse_pulse_shape(std::string_view text);  // "one-sine", "ricker"

class GroundMotion {
 public:
  // Samples at strictly increasing times, accelerations in m/s^2.
  static GroundMotion from_samples(std::string name, std::vector<double> times,
                                   std::vector<double> accelerations);
  // amplitude [m/s^2], period T [s] (Ricker: f = 1 / T).
  static GroundMotion pulse(PulseShape shape, double amplitude, double period);

  double acceleration(double t) const;       // a_g(t) [m/s^2]
  const std::vector<double>& breakpoints() const { return breakpoints_; }
  // A record: a_g is linear between consecutive breakpoints (a pulse is not).
  bool piecewise_linear() const { return !times_.empty(); }
  double duration() const { return duration_; }
  double peak() const;                       // max |a_g| [m/s^2]
  // Largest integrator step that still resolves a_g(t) between breakpoints:
  // period / 40 for a pulse (events that depend on a_g alone, such as a rigid
  // block's uplift, are otherwise invisible to the step-size control);
  // infinity for a record, whose samples are breakpoints.
  double max_step() const;
  const std::string& name() const { return name_; }
  GroundMotion scaled(double factor) const;  // a_g x factor

 private:
  std::string name_;
  std::vector<double> times_, values_;  // samples (empty for a pulse)
  double dt_ = 0;                        // > 0 when the samples are evenly spaced
  double inv_dt_ = 0;                    // 1 / dt_
  std::vector<double> breakpoints_;
  double duration_ = 0;
  PulseShape shape_ = PulseShape::one_sine;
  double amplitude_ = 0, period_ = 0, scale_ = 1;
};

enum class RecordFormat { automatic, at2, two_column, one_column };

struct RecordOptions {
  RecordFormat format = RecordFormat::automatic;  // .at2 or an NPTS header: AT2
  AccelerationUnit unit = AccelerationUnit::g;
  double dt = 0;       // one-column files only [s]
  double scale = 1;
};

GroundMotion read_record(const std::string& path, const RecordOptions& options = {});

}  // namespace rocking
