#!/usr/bin/env bash
# One entry point for users, developers and CI.
#
#   ./build.sh run    install what is missing, build sodaevo (Release; not the
#                     tests), run the main job
#   ./build.sh test   install what is missing, build the C++ libraries and their
#                     tests with AddressSanitizer + UBSan (into build-asan/) and
#                     run them, then build everything (Release, into build/: the
#                     WebAssembly engines, the Python module) and run the whole
#                     suite; a compiler warning or note in either build fails it
#   ./build.sh designer [MODEL]
#                     build the designer's WebAssembly engine (installs emscripten)
#                     and write designer.html, starting with MODEL if given
#   ./build.sh deps   only install the Debian packages the project needs
#   ./build.sh build  only configure and build (into build/), with the designer's
#                     WebAssembly engine (installs emscripten)
#   ./build.sh fuzz [SECONDS [TARGET...]]
#                     build the libFuzzer targets with clang-14 (into build-fuzz/)
#                     and run each for SECONDS (default 600); see fuzz/README.md
#
# Dependencies come from Debian packages only; they are installed with apt-get
# when missing (as root, or through sudo).
set -euo pipefail
cd "$(dirname "$0")"

BUILD_DIR=${SODAEVO_BUILD_DIR:-build}
ASAN_DIR=${SODAEVO_ASAN_DIR:-build-asan}
FUZZ_DIR=${SODAEVO_FUZZ_DIR:-build-fuzz}
# What `run` needs: the compiler and the libraries of the sodaevo binary.
PACKAGES=(g++ cmake ninja-build libpugixml-dev libcli11-dev nlohmann-json3-dev libeigen3-dev)
# The test suite (both builds of `test`, and `build`).
SUITE_PACKAGES=(catch2 zlib1g-dev)
# The optional MPI evaluator (evolve/mpi/, tested in the Release suite): Open MPI
# pulls in gfortran and some forty libraries, which the first result (`run`) does
# without; its binary says that MPI support is absent.
MPI_PACKAGES=(libopenmpi-dev openmpi-bin)
# Only the test suite needs these: headless Chromium opens the rendered pages.
TEST_PACKAGES=(chromium)
# The Python module (python/, docs/python.md) and its tests and examples; the
# build leaves the module out quietly without them, so `run` does not need them.
PYTHON_PACKAGES=(pybind11-dev python3-dev python3-numpy python3-pytest python3-deap python3-matplotlib)
# The designer's WebAssembly engine (web/, `sodaevo designer`): Debian's Emscripten.
WEB_PACKAGES=(emscripten)
# Only for `fuzz`: clang 14 and its runtime libraries (libclang_rt.fuzzer, asan, ubsan).
FUZZ_PACKAGES=(clang-14 libclang-rt-14-dev)

# The packages of PACKAGES and "$@" that are not installed.
missing_packages() {
  local p
  for p in "${PACKAGES[@]}" "$@"; do installed "$p" || echo "$p"; done
}

# apt-get as root, or through sudo.
apt_get() {
  local sudo=()
  [ "$(id -u)" -eq 0 ] || sudo=(sudo)
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get "$@"
}

# Whether the packages "$@" are all installed.
installed() {
  local p
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || return 1
  done
}

install_deps() {
  local missing
  mapfile -t missing < <(missing_packages "$@")
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "build.sh: installing missing Debian packages: ${missing[*]}"
  apt_get update -qq
  apt_get install -y -qq --no-install-recommends "${missing[@]}"
}

# install_deps "$@" in the background, its output into $BUILD_DIR/packages.log;
# wait_background_deps waits for it. Why: on a fresh machine the packages only the
# Release build needs (Emscripten, Chromium, the Python stack: minutes of download
# and unpacking) arrive while the sanitizer build, which needs none of them, compiles.
background_deps_pid=""
start_background_deps() {
  [ -n "$(missing_packages "$@")" ] || return 0
  [ "$(id -u)" -eq 0 ] || sudo -v # asks for a password here, not in the background
  mkdir -p "$BUILD_DIR"
  echo "build.sh: installing $(missing_packages "$@" | tr '\n' ' ')in the background (log: $BUILD_DIR/packages.log)"
  install_deps "$@" > "$BUILD_DIR/packages.log" 2>&1 &
  background_deps_pid=$!
}
wait_background_deps() {
  [ -n "$background_deps_pid" ] || return 0
  if ! wait "$background_deps_pid"; then
    cat "$BUILD_DIR/packages.log" >&2
    echo "build.sh: installing the packages failed (above)" >&2
    return 1
  fi
  background_deps_pid=""
}

# pugixml's source for the WebAssembly build: Debian ships pugixml only as a native
# library, and a copy of its source inside libopenimageio-dev, which is unpacked
# into $BUILD_DIR/wasm-deps (not installed: it would pull in 120 packages).
fetch_pugixml_source() {
  local dir="$BUILD_DIR/wasm-deps"
  [ -f "$dir/usr/include/OpenImageIO/detail/pugixml/pugixml.cpp" ] && return 0
  [ -f /usr/include/OpenImageIO/detail/pugixml/pugixml.cpp ] && return 0
  mkdir -p "$dir"
  echo "build.sh: unpacking pugixml's source from Debian's libopenimageio-dev into $dir"
  (cd "$dir" && { apt-get download libopenimageio-dev 2>/dev/null || { apt_get update -qq && apt-get download libopenimageio-dev; }; } &&
    dpkg-deb -x libopenimageio-dev_*.deb . && rm -f libopenimageio-dev_*.deb)
}

install_web_deps() {
  install_deps "${WEB_PACKAGES[@]}" "$@"
  fetch_pugixml_source
}

# Ninja for a new build folder (a folder configured before keeps its generator:
# CMake refuses to switch one).
generator_for() {
  [ -f "$1/CMakeCache.txt" ] || echo "-GNinja"
}

# build [TARGET...]: configure with the test suite, then build TARGETs (default:
# everything, tests included).
build() {
  cmake -S . -B "$BUILD_DIR" $(generator_for "$BUILD_DIR") -DCMAKE_BUILD_TYPE=Release -DSODAEVO_BUILD_TESTS=ON -DSODAEVO_MPI=ON
  cmake --build "$BUILD_DIR" -j "$(nproc)" ${1:+--target "$@"}
}

# The sodaevo binary alone, configured without the test suite (`run`, `designer`):
# the first result should not wait for Catch2. The same folder as `build`: a later
# `test` configures the suite back in and compiles only what is missing.
# With the MPI evaluator where Open MPI is installed (`run` does not install it).
build_sodaevo() {
  local mpi=OFF
  installed "${MPI_PACKAGES[@]}" && mpi=ON
  cmake -S . -B "$BUILD_DIR" $(generator_for "$BUILD_DIR") -DCMAKE_BUILD_TYPE=Release -DSODAEVO_BUILD_TESTS=OFF -DSODAEVO_MPI=$mpi
  cmake --build "$BUILD_DIR" -j "$(nproc)" --target sodaevo
}

# A fresh build prints no warning and no note, so a new one is news: the test
# path (CI) runs each build through this and fails on one. A log check rather
# than -Werror: it also catches notes (-Werror does not) and em++'s warnings from
# web/build_wasm.sh, and a user's `run` on a newer compiler still builds.
# (Incremental builds print only what they recompile; CI builds a fresh clone.)
fail_on_warnings() {
  local log
  log=$(mktemp)
  "$@" 2>&1 | tee "$log"
  if grep -E "warning:|note:|CMake Warning" "$log" > "$log.found"; then
    echo "build.sh: the build printed $(wc -l < "$log.found") line(s) with a warning or note (a clean build prints none):" >&2
    cat "$log.found" >&2
    rm -f "$log" "$log.found"
    return 1
  fi
  rm -f "$log" "$log.found"
}

# The C++ libraries and their tests with AddressSanitizer and UndefinedBehaviorSanitizer:
# what the sanitizers can see. Not the browser tests (the pages' JavaScript runs in
# Chromium, which no sanitizer here instruments; the C++ that writes the pages runs
# in the other tests too), not the Python module (the interpreter is not an
# instrumented program), not the WebAssembly engines (em++ output, not this
# compiler's; the Release build builds them once): so this build needs only the base
# packages and runs while the others install. -O1 so the suite stays fast, -g1
# (line tables: reports name file and line) so it builds fast; any finding aborts
# the test that hit it. Without the optional MPI evaluator: Open MPI keeps memory
# it never frees, which LeakSanitizer would report as findings of ours (the MPI
# tests run in the Release suite).
build_asan() {
  cmake -S . -B "$ASAN_DIR" $(generator_for "$ASAN_DIR") -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
    -DSODAEVO_SANITIZE=address,undefined -DSODAEVO_MPI=OFF -DSODAEVO_WASM=OFF -DSODAEVO_BROWSER_TESTS=OFF
  cmake --build "$ASAN_DIR" -j "$(nproc)"
}

run_asan_tests() {
  # detect_leaks: a leak is a finding too; halt_on_error: the first finding fails.
  export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:halt_on_error=1:abort_on_error=1:detect_stack_use_after_return=1}
  export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
  # Timing-sensitive tests run alone after the rest (RUN_SERIAL, tests/CMakeLists.txt).
  ctest --test-dir "$ASAN_DIR" --output-on-failure -j "$(nproc)"
}

build_fuzz() {
  CC=clang-14 CXX=clang++-14 cmake -S . -B "$FUZZ_DIR" $(generator_for "$FUZZ_DIR") -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" -DSODAEVO_BUILD_TESTS=OFF -DSODAEVO_FUZZ=ON -DSODAEVO_MPI=OFF \
    -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
  cmake --build "$FUZZ_DIR" -j "$(nproc)" --target fuzz_model_xml fuzz_run_config fuzz_checkpoint
}

case "${1:-}" in
  deps) install_deps "${SUITE_PACKAGES[@]}" "${MPI_PACKAGES[@]}" ;;
  build) install_web_deps "${SUITE_PACKAGES[@]}" "${MPI_PACKAGES[@]}"; build ;;
  run)
    # Only what the main job needs: the sodaevo binary, not the test suite.
    install_deps; build_sodaevo
    # The main job: evolve walkers from the default config into
    # results/default-<timestamp>/, then show how the Dainty Walker does.
    run_dir="results/default-$(date +%Y%m%d-%H%M%S)"
    "$BUILD_DIR/sodaevo" evolve configs/default.json --out "$run_dir"
    # The designer needs the WebAssembly engine (emscripten), which the first
    # result does not: it is one command away instead.
    best=$(ls "$run_dir"/best/gen_*.xml 2>/dev/null | tail -n 1)
    echo
    echo "Open the report in a browser: $run_dir/report.html"
    echo "Play with the champion in the designer (the first time installs emscripten and builds its engine):"
    echo "  ./build.sh designer ${best:-models/dainty_walker.xml}"
    ;;
  designer)
    install_web_deps; build_sodaevo
    "$BUILD_DIR/sodaevo" designer ${2:+"$2"} -o designer.html
    ;;
  test)
    # The sanitizer build first: it needs only the base packages, so the rest
    # install meanwhile (start_background_deps).
    install_deps "${SUITE_PACKAGES[@]}"
    start_background_deps "${WEB_PACKAGES[@]}" "${TEST_PACKAGES[@]}" "${PYTHON_PACKAGES[@]}" "${MPI_PACKAGES[@]}"
    fail_on_warnings build_asan
    run_asan_tests
    wait_background_deps
    install_web_deps "${SUITE_PACKAGES[@]}" "${TEST_PACKAGES[@]}" "${PYTHON_PACKAGES[@]}" "${MPI_PACKAGES[@]}"
    fail_on_warnings build
    ctest --test-dir "$BUILD_DIR" --output-on-failure -j "$(nproc)"
    ;;
  fuzz)
    install_deps "${FUZZ_PACKAGES[@]}"; build_fuzz
    shift
    SODAEVO_FUZZ_DIR="$FUZZ_DIR" fuzz/run.sh "$@"
    ;;
  *)
    # The header comment above, up to its first line that is not a comment.
    awk 'NR > 1 && !/^#/ { exit } NR > 1' "$0" | sed 's/^# \{0,1\}//'
    exit 2
    ;;
esac
