#!/usr/bin/env bash
# Builds the engine in WebAssembly with Debian's Emscripten (package `emscripten`):
#
#   web/build_wasm.sh OUT_DIR PUGIXML_DIR
#
# writes OUT_DIR/soda_engine_wasm.js, one file with the wasm inside (a page opened
# from a file cannot fetch a separate .wasm), a factory `createSodaEngine()` for
# pages, Web Workers (the designer's replica figure) and Node. web/soda_engine.js is the API over it.
#
# Compiled: web/engine_api.cpp, the engine's portable parts (model, reference step,
# the engine's own sine) and the XML reader and writer; not the SIMD steppers.
# PUGIXML_DIR holds pugixml.cpp: Debian ships pugixml only as a native library, so
# ./build.sh takes the source from Debian's libopenimageio-dev, which carries a copy
# (OpenImageIO/detail/pugixml; see web/README.md).
set -euo pipefail
out=${1:?usage: web/build_wasm.sh OUT_DIR PUGIXML_DIR}
pugixml=${2:?usage: web/build_wasm.sh OUT_DIR PUGIXML_DIR}
root=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$out"
# emcc's JavaScript tools need Debian's node modules (acorn) on the path.
export NODE_PATH=${NODE_PATH:-/usr/share/nodejs}

sources=("$root/web/engine_api.cpp" "$root/web/design_bytes.cpp" "$out/pugixml_oiio.cpp")
# The engine's portable files; the XML code may live in core/ or formats/.
for name in model model_def step input_error number_text printf_charconv xml_util xml_v1_reader xml_v1_writer \
  xml_v2_reader xml_escape model_file atomic_file sine java_sine_large sine_jitter fixed_bars cancellation; do
  for dir in core formats; do
    [ -f "$root/$dir/$name.cpp" ] && sources+=("$root/$dir/$name.cpp")
  done
done

# OpenImageIO's copy of pugixml sits in its namespace OIIO::pugi (with the alias
# `pugi`); these stand in for the OpenImageIO headers it includes.
mkdir -p "$out/oiio-stub/OpenImageIO"
printf '#pragma once\n#define OIIO_NAMESPACE_BEGIN namespace OIIO {\n#define OIIO_NAMESPACE_END }\n' \
  > "$out/oiio-stub/OpenImageIO/oiioversion.h"
printf '#pragma once\n#define OIIO_API\n' > "$out/oiio-stub/OpenImageIO/export.h"
printf '#include "%s/pugixml.cpp"\n' "$pugixml" > "$out/pugixml_oiio.cpp"

flags=(-std=c++20 -O3 -ffp-contract=off -fno-fast-math -fwasm-exceptions -DNDEBUG -include "$root/web/wasm_compat.hpp"
  -I"$root" -I"$pugixml" -I"$out/oiio-stub")
# Again only what changed: an object older than its source, or than any header of
# the engine (a coarse rule, but headers change seldom and the build is small).
headers=$(find "$root/core" "$root/web" "$root/formats" "$pugixml" -name '*.hpp' 2>/dev/null || true)
# Compiled in parallel, as many at a time as there are cores.
objects=()
pids=()
jobs_max=$(nproc)
mkdir -p "$out/obj"
for src in "${sources[@]}"; do
  obj="$out/obj/$(basename "${src%.cpp}").o"
  if [ ! -f "$obj" ] || [ -n "$(find "$src" $headers -newer "$obj" -print -quit)" ]; then
    rm -f "$obj"
    em++ "${flags[@]}" -c "$src" -o "$obj" &
    pids+=($!)
    if [ ${#pids[@]} -ge "$jobs_max" ]; then wait "${pids[0]}"; pids=("${pids[@]:1}"); fi
  fi
  objects+=("$obj")
done
for pid in "${pids[@]}"; do wait "$pid"; done
em++ "${flags[@]}" "${objects[@]}" -o "$out/soda_engine_wasm.js" \
  -sSINGLE_FILE=1 -sMINIFY_HTML=0 -sMODULARIZE=1 -sEXPORT_NAME=createSodaEngine \
  -sALLOW_MEMORY_GROWTH=1 -sENVIRONMENT=web,worker,node -sFILESYSTEM=0 \
  -sEXPORTED_FUNCTIONS=_malloc,_free \
  -sEXPORTED_RUNTIME_METHODS=UTF8ToString,stringToUTF8,lengthBytesUTF8
echo "build_wasm.sh: wrote $out/soda_engine_wasm.js ($(wc -c < "$out/soda_engine_wasm.js") bytes)"

# The evolution (web/evolve_api.cpp): evolve/, formats/ and the whole engine with
# its fast stepper, whose SSE2 kernels Emscripten compiles to 128-bit WebAssembly
# SIMD (-msimd128 -msse2; every operation is one IEEE operation per lane, so the
# bits are x86-64's). Not the AVX-512 lockstep batch (web/wasm_lockstep_stub.cpp).
# Its run folders live in the instance's memory file system. nlohmann/json and
# Eigen are Debian's headers; Eigen unvectorised (its x86 headers are not
# WebAssembly's; only the implicit integrators use it).
mkdir -p "$out/evolve-include"
ln -sfn /usr/include/nlohmann "$out/evolve-include/nlohmann"
evolve_sources=("$root/web/evolve_api.cpp" "$root/web/wasm_lockstep_stub.cpp" "$out/pugixml_oiio.cpp")
for src in "$root"/core/*.cpp "$root"/core/fused/*.cpp "$root"/formats/*.cpp "$root"/evolve/*/*.cpp; do
  case "$src" in */evolve/mpi/*) continue ;; esac
  case "$(basename "$src")" in lockstep_*.cpp) continue ;; esac
  evolve_sources+=("$src")
done
evolve_flags=("${flags[@]}" -msimd128 -msse2 -DEIGEN_DONT_VECTORIZE -DSODAEVO_HAS_MPI=0 -I"$out/evolve-include"
  -I/usr/include/eigen3)
evolve_headers=$(find "$root/core" "$root/web" "$root/formats" "$root/evolve" "$root/app" -name '*.hpp' 2>/dev/null || true)
evolve_objects=()
pids=()
mkdir -p "$out/evolve-obj"
for src in "${evolve_sources[@]}"; do
  rel=${src#"$root"/}
  obj="$out/evolve-obj/${rel//\//_}.o"
  if [ ! -f "$obj" ] || [ -n "$(find "$src" $evolve_headers -newer "$obj" -print -quit)" ]; then
    rm -f "$obj"
    em++ "${evolve_flags[@]}" -c "$src" -o "$obj" &
    pids+=($!)
    if [ ${#pids[@]} -ge "$jobs_max" ]; then wait "${pids[0]}"; pids=("${pids[@]:1}"); fi
  fi
  evolve_objects+=("$obj")
done
for pid in "${pids[@]}"; do wait "$pid"; done
em++ "${evolve_flags[@]}" "${evolve_objects[@]}" -o "$out/soda_evolve_wasm.js" \
  -sSINGLE_FILE=1 -sMINIFY_HTML=0 -sMODULARIZE=1 -sEXPORT_NAME=createSodaEvolve \
  -sALLOW_MEMORY_GROWTH=1 -sENVIRONMENT=web,worker,node -sFILESYSTEM=1 \
  -sEXPORTED_FUNCTIONS=_malloc,_free \
  -sEXPORTED_RUNTIME_METHODS=UTF8ToString,stringToUTF8,lengthBytesUTF8
echo "build_wasm.sh: wrote $out/soda_evolve_wasm.js ($(wc -c < "$out/soda_evolve_wasm.js") bytes)"
