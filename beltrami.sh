#!/usr/bin/env bash
# Beltrami set-up and entry point (Debian 12).
#   ./beltrami.sh demo   install what is missing, build, run the demo pipeline
#   ./beltrami.sh test   install what is missing, build, run the whole test suite
#   ./beltrami.sh build  install what is missing and build only
#   ./beltrami.sh docs   install what is missing, build the user guide (build/docs/html)
# Idempotent: a second run only rebuilds what changed.
set -euo pipefail
cd "$(dirname "$0")"
ROOT=$PWD
BUILD=${BELTRAMI_BUILD_DIR:-$ROOT/build}
action=${1:-demo}

PACKAGES=(
  # compiler and build tools
  g++ cmake ninja-build ccache
  # ParaView 5.11 SDK (VTK 9.2) and what its CMake config needs besides
  paraview-dev python3-paraview qtbase5-dev qttools5-dev qtxmlpatterns5-dev-tools
  libopenmpi-dev openmpi-bin libdouble-conversion-dev liblz4-dev
  # numerics and tests
  libeigen3-dev libgtest-dev python3-numpy xvfb xauth
  # volumes: TetGen, OpenVDB
  libtet1.5-dev libopenvdb-dev
  # sparse Cholesky for the parameterization (CHOLMOD) and a fast BLAS under it
  libsuitesparse-dev libopenblas0-pthread
  # algebraic multigrid for the large implicit solves (hypre's BoomerAMG)
  libhypre-dev
  # the remesher's constrained Delaunay triangulation (CGAL, header-only)
  libcgal-dev
  # line drawings as PDF (Cairo), and the readers the tests rasterise PDF and SVG with
  libcairo2-dev poppler-utils librsvg2-bin
  # the user guide (Sphinx, MyST Markdown, the furo theme)
  python3-sphinx python3-myst-parser furo
)

install_missing() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "== installing: ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -q
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
}

build() {
  if [ ! -f "$BUILD/build.ninja" ]; then
    local launcher=()
    command -v ccache >/dev/null && launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
    cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}"
  fi
  cmake --build "$BUILD" -- -j"$(nproc)"
}

case "$action" in
  build)
    install_missing
    build
    ;;
  demo)
    install_missing
    build
    # shellcheck disable=SC1091
    source "$BUILD/beltrami-env.sh"
    xvfb-run -a /usr/bin/python3 Examples/curvature_demo.py Testing/Data/bunny00.off "$ROOT/demo-output"
    xvfb-run -a /usr/bin/python3 Examples/smoothing_demo.py Testing/Data/bunny00.off "$ROOT/demo-output"
    # The same smoothing split over 2 ranks of pvbatch, solved over the ranks.
    xvfb-run -a mpirun --allow-run-as-root --oversubscribe -np 2 pvbatch \
      Examples/distributed_smoothing_demo.py Testing/Data/bunny00.off "$ROOT/demo-output"
    xvfb-run -a /usr/bin/python3 Examples/parameterization_demo.py Testing/Data/mushroom.off "$ROOT/demo-output"
    xvfb-run -a /usr/bin/python3 Examples/remeshing_demo.py "$ROOT/demo-output"
    xvfb-run -a /usr/bin/python3 Examples/line_drawing_demo.py "$ROOT/demo-output"
    xvfb-run -a /usr/bin/python3 Examples/vector_field_demo.py "$ROOT/demo-output"
    /usr/bin/python3 Examples/denoising_demo.py "$ROOT/demo-output"
    ;;
  docs)
    install_missing
    /usr/bin/python3 -m sphinx -W --keep-going -q -b html docs "$BUILD/docs/html"
    echo "== the user guide: $BUILD/docs/html/index.html"
    ;;
  test)
    install_missing
    build
    cd "$BUILD"
    ctest --output-on-failure -j"$(nproc)"
    ;;
  *)
    echo "usage: $0 [demo|test|build|docs]" >&2
    exit 2
    ;;
esac
