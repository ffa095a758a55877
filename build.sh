#!/usr/bin/env bash
# One entry point for users, developers and CI.
#
#   ./build.sh run    install what is missing, build (Release), run the main job
#   ./build.sh test   install what is missing, build, run the whole test suite
#   ./build.sh deps   only install the Debian packages the project needs
#   ./build.sh build  only configure and build (into build/)
#
# Dependencies come from Debian packages only; they are installed with apt-get
# when missing (as root, or through sudo).
set -euo pipefail
cd "$(dirname "$0")"

BUILD_DIR=${SODAEVO_BUILD_DIR:-build}
PACKAGES=(g++ cmake make libpugixml-dev libcli11-dev nlohmann-json3-dev catch2 libopenmpi-dev openmpi-bin)
# Only the test suite needs these: headless Chromium opens the rendered pages.
TEST_PACKAGES=(chromium)

install_deps() {
  local missing=()
  for p in "${PACKAGES[@]}" "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "build.sh: installing missing Debian packages: ${missing[*]}"
  local sudo=()
  [ "$(id -u)" -eq 0 ] || sudo=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo[@]}" apt-get update -qq
  "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

build() {
  cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
  cmake --build "$BUILD_DIR" -j "$(nproc)"
}

case "${1:-}" in
  deps) install_deps ;;
  build) install_deps; build ;;
  run)
    install_deps; build
    # The main job: evolve walkers from the default config into
    # results/default-<timestamp>/, then show how the Dainty Walker does.
    "$BUILD_DIR/sodaevo" evolve configs/default.json
    ;;
  test)
    install_deps "${TEST_PACKAGES[@]}"; build
    ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$(nproc)"
    ;;
  *)
    sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'
    exit 2
    ;;
esac
