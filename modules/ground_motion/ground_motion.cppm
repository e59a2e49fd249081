// rocking.ground_motion: the horizontal ground acceleration a_g(t) [m/s^2]
// (MODEL.md 10), with the vertical a_v(t) (upward) that comes with it when
// one is given, and the other horizontal component recorded with it when
// one is read (MODEL.md 14): two orthogonal components a_1, a_2 project on
// the plane at azimuth phi from the first toward the second as
// a_1 cos phi + a_2 sin phi. A record is piecewise linear between its samples, which are
// breakpoints for the integrator; it is zero before its first and after its
// last sample. The files the field keeps records in are read by
// rocking.records.
// Units g, m/s2, cm/s2 (gal) or mm/s2 (g = 9.81 m/s^2, rocking.geometry's gravity).
// Analytic pulses for tests, teaching and the default excitation:
//   one-sine: a(t) = A sin(2 pi t / T) on [0, T] (Makris & Roussos 2000),
//   Ricker:   a(t) = A (1 - 2 u) exp(-u), u = (pi f (t - t0))^2, t0 = 1.5 / f.
// Records are processed as the field does it when asked (Processing,
// processing.cpp): cut, polynomial detrend, cosine taper, a zero-phase
// Butterworth band-pass, the velocity-fit baseline correction and
// resampling, before any use of the record; the record then says so
// (RecordInfo::processing, its description).
// A component's orientation is read from its name (component_orientation):
// a vertical one is refused as the horizontal motion and a horizontal one as
// the vertical (MODEL.md 14), where the name tells.
module;
#include <algorithm>
#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>
export module rocking.ground_motion;
export import rocking.geometry;  // gravity

export namespace rocking {

enum class AccelerationUnit { g, m_per_s2, cm_per_s2, mm_per_s2 };
// "g", "m/s2", "cm/s2" (or "gal"), "mm/s2"; InputError otherwise.
AccelerationUnit parse_acceleration_unit(std::string_view text);
std::string unit_name(AccelerationUnit unit);  // "g", "m/s2", "cm/s2", "mm/s2"
double to_si(AccelerationUnit unit);  // factor to m/s^2

// What a record file says about itself; empty where it says nothing.
struct RecordInfo {
  std::string format;     // the reader's name ("at2", "geonet", ...)
  std::string event, date, station, component;
  std::string units;      // the unit of the file's numbers, as read ("mm/s2", "g")
  double dt = 0;          // sample interval [s]; 0 when the times are uneven
  std::size_t npts = 0;   // samples read
  std::optional<double> stated_peak;  // |peak| the file states [m/s^2] (none once processed)
  std::string processing;  // how it was processed (Processing::describe); empty: as recorded
  // "event, station, component" from what is known ("" when none is).
  std::string label() const;
};

// What a component's name says of its direction: "Up", "DWN", "V", "U-D"
// (K-NET), "HNZ" (a SEED channel) are vertical; "N28W", "E-W", "090", "S",
// "L", "HN1" horizontal; other names say nothing.
enum class Orientation { unknown, horizontal, vertical };
Orientation component_orientation(std::string_view name);

enum class PulseShape { one_sine, ricker };
PulseShape parse_pulse_shape(std::string_view text);  // "one-sine", "ricker"

// Accelerations beyond this are not ground motion: records holding them are
// refused at their line, and no scaling may take a motion there.
inline constexpr double max_acceleration_g = 100;  // |a| [g]
// Records beyond these are not records: refused (by every reader, and by
// GroundMotion::from_samples) rather than run into a non-finite state or an
// absurd amount of work.
inline constexpr double max_record_duration = 1e5; // [s], about 28 hours
inline constexpr double min_record_dt = 1e-6;      // [s]
inline constexpr double max_scale_factor = 1e3;    // |factor| a scene may put on its excitation

class GroundMotion {
 public:
  // Samples at strictly increasing times, accelerations in m/s^2.
  static GroundMotion from_samples(std::string name, std::vector<double> times,
                                   std::vector<double> accelerations);
  // Samples every dt [s] from t = 0 (at least two).
  static GroundMotion evenly_sampled(std::string name, double dt, std::vector<double> accelerations);
  // amplitude [m/s^2], period T [s] (Ricker: f = 1 / T).
  static GroundMotion pulse(PulseShape shape, double amplitude, double period);

  // a_g(t) [m/s^2]. For a record sampled evenly from t = 0 (every
  // right-hand side and guard of a run asks) no search, no division and no
  // chain of loads; defined here so that the link-time optimiser can inline
  // it into its callers (a member defined in a named module's class is not
  // implicitly inline: without LTO, callers call it).
  double acceleration(double t) const {
    if (even_values_ != nullptr && t >= 0 && t <= duration_) {
      const double x = t * even_inv_dt_;
      const std::size_t i = std::min(static_cast<std::size_t>(x), even_last_);
      const double s = x - static_cast<double>(i);
      return scale_ * ((1 - s) * even_values_[i] + s * even_values_[i + 1]);
    }
    return acceleration_otherwise(t);
  }
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
  const RecordInfo& info() const { return info_; }
  void set_info(RecordInfo info) { info_ = std::move(info); }
  // A record's samples as scaled (empty for a pulse): times [s] and a_g [m/s^2].
  std::vector<double> sample_times() const;
  std::vector<double> sample_values() const;
  double scale() const { return scale_; }
  // The interval of evenly spaced samples from t = 0 [s]; 0 otherwise.
  double sample_interval() const { return samples_ ? samples_->dt : 0.0; }
  GroundMotion scaled(double factor) const;  // a_g (and a_v) x factor; shares the samples
  // The vertical motion that comes with this one (upward; MODEL.md 14), as
  // scaled with it, or null: a run under this motion feels both.
  const GroundMotion* vertical() const { return vertical_.get(); }
  GroundMotion with_vertical(const GroundMotion& v) const;  // its own vertical motion dropped
  // The other horizontal component recorded with this one, 90 degrees on from
  // it (for RotD spectra and projections), as scaled with it, or null.
  const GroundMotion* other_horizontal() const { return other_.get(); }
  GroundMotion with_other_horizontal(const GroundMotion& h) const;  // its own others dropped

 private:
  friend class GroundTravel;
  // A record's samples, shared by its scaled copies (a study runs many).
  // Evenly spaced from t = 0 (as records are), times are i dt and not stored.
  struct Samples {
    std::vector<double> times;   // empty when evenly spaced
    std::vector<double> values;  // [m/s^2]
    double dt = 0, inv_dt = 0;   // > 0 when evenly spaced
    double peak = 0;             // max |value| [m/s^2]
  };
  double time_of(std::size_t i) const;
  double acceleration_otherwise(double t) const;  // a pulse, uneven samples, or t outside the record
  // samples_ and, when they are evenly spaced, the even_ fields from them:
  // the only way samples_ is set, so that the two always agree.
  void set_samples(std::shared_ptr<const Samples> samples);

  std::string name_, description_;
  RecordInfo info_;
  std::shared_ptr<const Samples> samples_;  // null for a pulse
  std::shared_ptr<const GroundMotion> vertical_;  // null: none
  std::shared_ptr<const GroundMotion> other_;     // null: none
  double duration_ = 0;
  PulseShape shape_ = PulseShape::one_sine;
  double amplitude_ = 0, period_ = 0, scale_ = 1;
  // Evenly spaced samples (from samples_, which keeps them alive: copies
  // share them): the first value, 1 / dt and the last interval's first
  // index; null when not evenly spaced (set_samples).
  const double* even_values_ = nullptr;
  double even_inv_dt_ = 0;
  std::size_t even_last_ = 0;
};

// The ground's velocity and displacement from rest at t = 0 (before a
// record's first sample the ground is at rest): a record's exact integrals of
// its piecewise-linear a_g (v quadratic and d cubic between samples; no
// baseline correction), a pulse's closed forms (one-sine:
// v = A / w (1 - cos w t), d = A / w (t - sin(w t) / w) on [0, T]; Ricker:
// v = A [tau e^(-b^2 tau^2)] and d = A [-e^(-b^2 tau^2) / (2 b^2)] + ... from
// t = 0, tau = t - t0, b = pi / T). Asked at times that do not decrease (a
// history's rows), it walks a record's samples once in all; an earlier time
// starts the walk again.
class GroundTravel {
 public:
  explicit GroundTravel(const GroundMotion& g) : g_(&g) {}
  struct State {
    double v = 0, d = 0;  // [m/s], [m]
  };
  State at(double t);

 private:
  const GroundMotion* g_;
  std::size_t next_ = 0;          // the walk has passed samples 0 .. next_ - 1
  double v_ = 0, d_ = 0;          // at sample next_ - 1
};

// Record processing (gmprocess's and PEER's steps), in this order:
//   cut to [t0, t1], shifted to start at t = 0;
//   detrend: the least-squares polynomial of the given order removed from a
//     (order 0: the mean);
//   taper: a cosine (Tukey) taper over the given fraction of the record at each end;
//   band-pass: a Butterworth high-pass and low-pass of the given order, run
//     forward and then backward over the record (zero phase: the magnitude
//     response squared);
//   velocity fit: a polynomial of the given order fit to the velocity (the
//     record's exact integral from rest) by least squares, its derivative
//     removed from a (Boore 2005's baseline correction);
//   resampling at a new interval (the piecewise-linear record read at the new times).
// The Butterworth sections (butterworth()): the analog prototype's poles
// -sin(theta_k) +- i cos(theta_k), theta_k = pi (2k - 1) / (2n), at the
// prewarped corner W_c = tan(pi f_c dt), through the bilinear transform
// s = (1 - z^-1) / (1 + z^-1), so that |H(f)|^2 = 1 / (1 + (W / W_c)^(2n))
// (low-pass) or 1 / (1 + (W_c / W)^(2n)) (high-pass), W = tan(pi f dt)
// (Oppenheim & Schafer, Discrete-Time Signal Processing, 7.1).
struct Processing {
  std::optional<std::array<double, 2>> cut;  // [t0, t1] [s]
  int detrend = -1;                 // order; -1: none
  double taper = 0;                 // fraction at each end, 0 to 0.5
  double highpass = 0, lowpass = 0; // corners [Hz]; 0: none
  int order = 4;                    // Butterworth order of each
  int velocity_fit = -1;            // order; -1: none
  double dt = 0;                    // resample at [s]; 0: keep
  bool any() const { return cut || detrend >= 0 || taper > 0 || highpass > 0 || lowpass > 0 || velocity_fit >= 0 || dt > 0; }
  // "cut 5-60 s, detrend 1, taper 5 %, Butterworth 0.1-25 Hz order 4 zero-phase, velocity fit 2, dt 0.01 s"
  std::string describe() const;
};
// "highpass=0.1,lowpass=25,order=4,taper=0.05,detrend=1,vfit=2,cut=5:60,dt=0.01",
// any of them in any order; InputError of one line naming the part otherwise
// (callers say where the text came from).
Processing parse_processing(std::string_view text);
// The record processed (InputError for a pulse, a corner at or above the
// Nyquist frequency, a cut outside the record).
GroundMotion process(const GroundMotion& g, const Processing& p);
// One biquad: y = (b0 + b1 z^-1 + b2 z^-2) / (1 + a1 z^-1 + a2 z^-2) x.
struct SecondOrderSection {
  double b0 = 1, b1 = 0, b2 = 0, a1 = 0, a2 = 0;
};
std::vector<SecondOrderSection> butterworth(int order, double corner_hz, double dt, bool highpass);
// |H(f)| of the sections in cascade (one pass).
double magnitude(const std::vector<SecondOrderSection>& sections, double f_hz, double dt);
// The sections run forward, then backward: zero phase, |H|^2.
std::vector<double> zero_phase(const std::vector<SecondOrderSection>& sections, std::vector<double> x);
std::vector<double> detrend(const std::vector<double>& a, double dt, int order);
std::vector<double> velocity_fit(const std::vector<double>& a, double dt, int order);
std::vector<double> cosine_taper(std::vector<double> a, double fraction);

// What a record is read as: a component whose name says otherwise is refused
// (component_orientation). `rocking record` measures any.
enum class ReadAs { horizontal, vertical, any };

struct RecordOptions {
  std::string format = "auto";            // "auto" (from the content) or a name of record_formats()
  std::optional<AccelerationUnit> unit = {};  // unset: the file's own (g where a file states none)
  std::string component = {};  // a file of several components (GeoNet) or columns (CSV): name or 1-based index
  double dt = 0;          // one-column files only [s]
  double scale = 1;
  ReadAs read_as = ReadAs::horizontal;
  // A component of the same file read as the vertical motion that comes with
  // this one (GroundMotion::vertical: a GeoNet file's "Up"); empty: none.
  std::string vertical_component = {};
  // Read the file's other horizontal component with this one
  // (GroundMotion::other_horizontal): InputError when it holds none.
  bool other_horizontal = false;
  Processing process = {};  // applied to every component read
};

// cos and sin of an angle in degrees, exactly 0 and +-1 at multiples of 90.
std::array<double, 2> direction_cosines(double degrees);

// Two horizontal components recorded together, on one time base: each one's
// samples every dt from t = 0, the shorter padded with zeros. InputError
// unless both are records sampled evenly at one interval.
struct HorizontalPair {
  double dt = 0;
  std::vector<double> first, second;  // [m/s^2]
};
HorizontalPair pair_components(const GroundMotion& first, const GroundMotion& second);
// The projection on the plane at `degrees` from the first component toward
// the second (exactly the first at 0, the second at 90), named so; its other
// horizontal the projection 90 degrees on, its vertical the first's.
GroundMotion project(const GroundMotion& first, const GroundMotion& second, double degrees);

}  // namespace rocking
