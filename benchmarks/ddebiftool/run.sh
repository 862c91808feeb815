#!/usr/bin/env bash
# Cross-check of slopetui's periodic-orbit continuation with DDE-BIFTOOL in GNU Octave.
# Usage: DDEBIFTOOL=/path/to/DDE-Biftool bash run.sh [all|tau10|folds|hopfcurve|pofoldcurve|threeslip|torus]
#    or: bash run.sh /path/to/DDE-Biftool [all|...]   (needs: apt-get install octave)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
if [[ $# -ge 1 && -d "$1" ]]; then export DDEBIFTOOL="$1"; shift; fi
: "${DDEBIFTOOL:?set DDEBIFTOOL or pass the DDE-BIFTOOL directory as first argument}"
[[ -d "$DDEBIFTOOL/ddebiftool" ]] || { echo "no ddebiftool/ under $DDEBIFTOOL" >&2; exit 2; }
what="${1:-all}"
cd "$here"
oct() { octave --no-gui --quiet --eval "$1"; }
if [[ "$what" == all || "$what" == tau10 ]]; then
  octave --no-gui --quiet run_tau10.m 2>&1 | tee tau10.log
  # both read tau10_results.mat written by run_tau10.m
  octave --no-gui --quiet compare_points.m 2>&1 | tee compare_points.log
  octave --no-gui --quiet mesh_check.m 2>&1 | tee mesh_check.log
fi
if [[ "$what" == all || "$what" == folds ]]; then
  # fold_tau(tau, k to start the steady-state sweep below the Hopf point, degree, intervals)
  for spec in "2,8.0" "5,5.5" "20,5.0"; do
    oct "setup_path(); fold_tau(${spec},4,60)" 2>&1 | tee "fold_tau${spec%%,*}.log"
  done
fi
if [[ "$what" == all || "$what" == hopfcurve ]]; then
  # first Hopf curve in (k, tau), l1 along it, the Bautin point; l1 checked on orbit amplitudes
  octave --no-gui --quiet mfderi_check.m 2>&1 | tee mfderi_check.log
  oct "hopf_curve(0.1,20)" 2>&1 | grep -v '^BR_CONTN' | tee hopf_curve.log
  oct "hopf_curve(0.3,20,2)" 2>&1 | grep -v '^BR_CONTN' | tee hopf2_curve.log
  for spec in "0.5,35" "2,8.0" "10,4.0"; do oct "l1_check($spec)"; done 2>&1 \
    | grep -v '^BR_CONTN' | tee l1_check.log
  oct "l1_check(5,6,2,10)" 2>&1 | grep -v '^BR_CONTN' | tee l1_check2.log   # second Hopf curve
fi
if [[ "$what" == all || "$what" == pofoldcurve ]]; then
  # fold of cycles continued in (k, tau) from tau = 10, down to 2 and up to 20
  oct "pofold_curve(2,20)" 2>&1 | grep -v '^BR_CONTN' | tee pofold_curve.log
  # and down to the Bautin point, where it meets the Hopf curve (needs hopfcurve's .mat)
  oct "pofold_curve(0.6,10)" 2>&1 | grep -v '^BR_CONTN' | tee pofold_curve_low.log
  oct "fold_meets_hopf('pofold_curve_0.6_10.mat','hopf_curve1_results.mat')" 2>&1 \
    | grep -v '^BR_CONTN' | tee fold_meets_hopf.log
  # mesh check on the curve's low part: the fold at tau = 1 on 60 and 120 intervals
  for n in 60 120; do oct "setup_path(); fold_tau(1,13,4,$n)"; done 2>&1 \
    | grep -v '^BR_CONTN' | tee fold_tau1_mesh.log
fi
if [[ "$what" == all || "$what" == threeslip ]]; then
  # the seed (Newton's starting guess only) is slopetui's 3-slip seed; it is tracked,
  # rewrite it with the repository's venv: PYSEED=1 bash run.sh <dir> threeslip
  if [[ -n "${PYSEED:-}" ]]; then
    ../../.venv/bin/python write_seed.py 18 10 1e-6 3 threeslip_seed.txt
  fi
  for n in 60 120; do oct "threeslip($n)"; done 2>&1 | tee threeslip.log
fi
if [[ "$what" == all || "$what" == torus ]]; then
  # the 2-slip orbit's torus: secant on |mu| - 1 and SetupTorusBifurcation at fixed tau
  # (tau, slopetui's k, and the steady-state sweep that finds the second Hopf point)
  for spec in "10,5.2567084,5.5,2" "10.5,4.927606587,5.5,2" "20,2.2231999,5.5,1.5" \
              "8.56365,6.4813,5.5,2.5" "5.162098,13.373043,5.5,4.5"; do
    oct "torus('point',4,60,$spec)" 2>&1 | grep -v '^BR_CONTN' | tee "torus_point_${spec%%,*}.log"
  done
  # the 3-slip orbit's torus at tau = 10 (third Hopf point, pairs near exp(+-2 pi i/3))
  oct "torus('point',4,60,10,9.8622765,5.5,4.5,3)" 2>&1 | grep -v '^BR_CONTN' | tee torus_point_10_3slip.log
  oct "torus('point',4,120,10,9.8622765,5.5,4.5,3)" 2>&1 | grep -v '^BR_CONTN' | tee torus_point_10_3slip_n120.log
  oct "torus('point',4,120,10,5.2567084,5.5,2)" 2>&1 | grep -v '^BR_CONTN' | tee torus_point_10_n120.log
  # the curve in (k, tau) from tau = 10 (reads torus_point_10.mat: rerun the first line
  # before it, as the 120-interval run above rewrites it), 50 s a point
  oct "torus('point',4,60,10,5.2567084,5.5,2)" > /dev/null 2>&1
  oct "torus('curve:9.9:10.5')" 2>&1 | grep -v '^BR_CONTN' | tee torus_curve_10.5.log
fi
