#!/usr/bin/env bash
# Makes the synthetic cyclic tests of data/tests with the project's own laws
# (build/bin/make_cyclic_test, after `make build`): two sine cycles at each
# amplitude, force noise of 1 % of the peak force (Gaussian, GSL mt19937,
# seed 1). tests/fitting_test.cpp holds the parameters stated here.
set -euo pipefail
cd "$(dirname "$0")/.."
make_test=build/bin/make_cyclic_test
mkdir -p data/tests
# A yielding metallic plate: k 2e7 N/m, eps 0.05, d_y 4 mm, alpha 0.7, beta 0.3, n 1.5; 0.5 Hz.
"$make_test" --law bouc-wen --param k=2e7 --param eps=0.05 --param d_y=0.004 --param alpha=0.7 \
  --param beta=0.3 --param n=1.5 --amplitudes 0.002,0.004,0.008,0.016,0.024 --frequency 0.5 \
  --noise 0.01 --seed 1 --out data/tests/bouc_wen_cyclic.csv
# A prestressed tendon: P0 5e4 N, k 3e6 N/m; 0.5 Hz.
"$make_test" --law elastic --param P0=5e4 --param k=3e6 --amplitudes 0.005,0.01 --frequency 0.5 \
  --noise 0.01 --seed 1 --out data/tests/elastic_cyclic.csv
# A fluid viscous damper: c 2e5 N (s/m)^0.4, a 0.4; 2 Hz.
"$make_test" --law viscous --param c=2e5 --param a=0.4 --amplitudes 0.005,0.01,0.02 --frequency 2 \
  --noise 0.01 --seed 1 --out data/tests/viscous_cyclic.csv
