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
#include <memory>
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
  // The first breakpoint (a record's sample, a pulse's end) strictly after t,
  // or +infinity: computed, not listed, so that a run holds no copy of them.
  double next_breakpoint(double t) const;
  std::size_t sample_count() const;          // 0 for a pulse
  // A record: a_g is linear between consecutive breakpoints (a pulse is not).
  bool piecewise_linear() const { return samples_ != nullptr; }
  double duration() const { return duration_; }
  double peak() const;                       // max |a_g| [m/s^2]
  // Largest integrator step that still resolves a_g(t) between breakpoints:
  // period / 40 for a pulse (events that depend on a_g alone, such as a rigid
  // block's uplift, are otherwise invisible to the step-size control);
  // infinity for a record, whose samples are breakpoints.
  double max_step() const;
  const std::string& name() const { return name_; }
  // What the record's own header says it is, with its PGA before scaling
  // ("El Centro 1940 North South Component, PGA 0.32 g"); empty when the file
  // has no header.
  const std::string& description() const { return description_; }
  void set_description(std::string text) { description_ = std::move(text); }
  GroundMotion scaled(double factor) const;  // a_g x factor; shares the samples

 private:
  // A record's samples, shared by its scaled copies (a study runs many).
  // Evenly spaced from t = 0 (as records are), times are i dt and not stored.
  struct Samples {
    std::vector<double> times;   // empty when evenly spaced
    std::vector<double> values;  // [m/s^2]
    double dt = 0, inv_dt = 0;   // > 0 when evenly spaced
  };
  double time_of(std::size_t i) const;

  std::string name_, description_;
  std::shared_ptr<const Samples> samples_;  // null for a pulse
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
