// rocking.intensity: what a ground motion is, in the measures of the field
// (MODEL.md 12). For a record a(t), piecewise linear between its samples:
//   PGA = max|a|; v and d by exact integration (v piecewise quadratic, d
//   cubic, both zero at t = 0, no baseline correction), PGV and PGD their
//   peaks including those between samples;
//   Arias intensity I_A = pi / (2 g) int a^2 dt; D5-95 the time between 5 %
//   and 95 % of I_A; CAV = int |a| dt (all exact for the piecewise-linear a);
//   PSA(T, zeta) = w^2 max|x| for x'' + 2 zeta w x' + w^2 x = -a(t), w = 2 pi / T,
//   from rest, over the record's duration. Each step is exact for the linear
//   a (the first-order-hold, or piecewise-exact, step of Nigam & Jennings,
//   BSSA 59, 1969; the same discretisation as rocking.integrator's full
//   contact); steps are cut to at most T / 20 and the peak between two
//   points is located where x' = 0, so a short period's peak between samples
//   is caught.
// RotD50 and RotD100 (Boore 2010; MODEL.md 14) of two horizontal components
// recorded together: the median and the maximum over azimuths phi = 0..179
// degrees (1 degree steps) of PSA(T) of the projection a1 cos phi + a2 sin phi.
// The oscillator is linear, so each azimuth's response is x1 cos phi +
// x2 sin phi of the components' responses, stepped once; its peak is located
// between steps as PSA's is. The median of the 180 is the mean of the middle two.
// Intensity measures for scaling (MODEL.md 12): the scale factor that brings
// a record's IM to a level is level / IM(record), since every IM here is
// proportional to the acceleration's scale.
module;
#include <array>
#include <string>
#include <string_view>
#include <vector>
export module rocking.intensity;
import rocking.ground_motion;

export namespace rocking {

// a, v, d at the record's samples [m/s^2, m/s, m].
struct GroundHistory {
  std::vector<double> t, a, v, d;
};
GroundHistory integrate_record(const GroundMotion& g);

struct RecordMeasures {
  double pga = 0, pga_time = 0;  // [m/s^2], [s]
  double pgv = 0;                // [m/s]
  double pgd = 0;                // [m]
  double arias = 0;              // [m/s]
  double d5_95 = 0;              // [s]
  double t5 = 0, t95 = 0;        // [s]: where 5 % and 95 % of I_A are reached
  double cav = 0;                // [m/s]
  double damping = 0.05;
  std::vector<double> periods;   // [s]
  std::vector<double> psa;       // [m/s^2], one per period
};
// InputError for a pulse (not a record), a period not positive and finite,
// or a damping outside [0, 1).
RecordMeasures measure_record(const GroundMotion& g, const std::vector<double>& periods, double damping = 0.05);
// The strong shaking of a record, for time axes: from 5 % to 95 % of its
// Arias intensity, widened by a quarter of that span (at least 2 s) each
// side, within the record [s]. InputError for a pulse.
std::array<double, 2> strong_shaking_window(const GroundMotion& g);
// PSA(T, zeta) [m/s^2].
double pseudo_spectral_acceleration(const GroundMotion& g, double period, double damping = 0.05);
std::vector<double> response_spectrum(const GroundMotion& g, const std::vector<double>& periods, double damping = 0.05);
// RotD50 and RotD100 at each period [m/s^2]; InputError as pair_components,
// or for a period or damping PSA refuses.
struct RotD {
  double rotd50 = 0, rotd100 = 0;
};
std::vector<RotD> rotd_spectrum(const GroundMotion& first, const GroundMotion& second,
                                const std::vector<double>& periods, double damping = 0.05);
// The periods of the NGA-West2 spectra from 0.01 to 10 s (21 of them).
// Oscillator periods the spectra resolve in doubles: from 1 ms (a stiff
// oscillator follows the ground: PSA -> PGA) to 1000 s.
inline constexpr double shortest_period = 1e-3, longest_period = 1e3;
// InputError unless T is in [shortest_period, longest_period].
void check_period(double T);

std::vector<double> standard_periods();
// n periods evenly spaced in log T from `from` to `to` (for smooth figures).
std::vector<double> log_periods(double from, double to, int n);

// An intensity measure to scale records to: "sf" (the factor itself), "pga",
// "pgv", "sa:T" (PSA at T), "saavg:T1:T2" (the geometric mean of PSA at 10
// periods evenly spaced in log T from T1 to T2), "rotd50:T" and "rotd100:T"
// (of the record and its other horizontal component, GroundMotion::other_horizontal).
struct IntensityMeasure {
  enum class Kind { scale_factor, pga, pgv, sa, saavg, rotd50, rotd100 } kind = Kind::scale_factor;
  bool needs_pair() const { return kind == Kind::rotd50 || kind == Kind::rotd100; }
  double t1 = 0, t2 = 0;     // [s]
  double damping = 0.05;
  std::string name() const;  // as parsed: "sa:1", "pga"
  std::string unit() const;  // "g", "m/s", "" (scale factor)
};
// A period may be written T1 or kT1 (0.2T1) when first_period [s] is given:
// sa:T1 is PSA at the structure's first period.
IntensityMeasure parse_intensity_measure(std::string_view text, double damping = 0.05, double first_period = 0);
// The record's IM in the unit of IntensityMeasure::unit() (1 for "sf");
// InputError for RotD of a record without its other horizontal component.
double intensity(const GroundMotion& g, const IntensityMeasure& im);

}  // namespace rocking
