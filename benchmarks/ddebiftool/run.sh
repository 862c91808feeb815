#!/usr/bin/env bash
# Cross-check of slopetui's periodic-orbit continuation with DDE-BIFTOOL in GNU Octave.
# Usage: DDEBIFTOOL=/path/to/DDE-Biftool bash run.sh [all|tau10|folds]   (needs: apt-get install octave)
#    or: bash run.sh /path/to/DDE-Biftool [all|tau10|folds]
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
