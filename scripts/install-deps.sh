#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs the Debian packages dvi needs that are not yet on the machine.
# Usage: install-deps.sh [extra-package ...]
set -euo pipefail

packages=(
  cmake g++ make pkg-config
  libeigen3-dev          # dense linear algebra everywhere
  libsundials-dev        # CVODE / IDA (integrators), SUNLinSol_KLU
  libsuitesparse-dev     # KLU sparse LU for large sparse Jacobians
  libboost-dev           # Boost.Odeint adapter (header-only)
  nlohmann-json3-dev     # scene and problem files, JSON answers
  libcli11-dev           # dvisim's command line
  libginac-dev           # scene expressions: parsing and exact symbolic derivatives
  gnuplot-nox            # dvisim run's plots (pngcairo and svg terminals)
  libopenmpi-dev openmpi-bin  # ensembles and dvisim sweep over MPI ranks, and their 2-rank test
  libpetsc-real-dev      # the PETSc back-end of boundary-value solves (dvi::petsc, DVI_PETSC) and its tests
  chromium               # the study page's browser test (label browser; 30-40 s and ~370 MB to install here, ~6 s to run)
  libgtest-dev libgmock-dev  # the test suites
  libbenchmark-dev       # bench/
  python3-pybind11 pybind11-dev python3-numpy python3-pytest  # the Python module (python/) and its tests
  python3-scipy          # scipy.sparse input to dvi.Lcs, tested by python/tests/test_sparse_lcs.py
  python3-matplotlib     # python/examples/diode_bridge.py, drawn by its test
  "$@"
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "Installing missing Debian packages: ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
