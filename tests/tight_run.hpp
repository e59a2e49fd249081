// Run options at tolerances tight enough for closed-form comparisons (1e-8):
// rtol 1e-12, atol 1e-14, for `duration` seconds, released from a tilt theta0.
#pragma once
import rocking.simulation;

inline rocking::RunOptions tight(double duration, double theta0 = 0) {
  rocking::RunOptions o;
  o.tolerances.rtol = 1e-12;
  o.tolerances.atol = 1e-14;
  o.duration = duration;
  o.initial.theta = theta0;
  return o;
}
