# web/: the engine in WebAssembly and the designer page, embedded into the sodaevo
# binary for `sodaevo designer` (included by the top CMakeLists.txt).
#
# The WebAssembly engine is optional: it needs Debian's emscripten (em++) and
# pugixml's source (Debian ships pugixml only as a native library; ./build.sh
# unpacks the copy in Debian's libopenimageio-dev, web/README.md says why). Without
# them the native build is unchanged and `sodaevo designer` says what is missing.
option(SODAEVO_WASM "Build the WebAssembly engine for `sodaevo designer` when em++ is found" ON)
find_program(SODAEVO_EMXX em++)
set(_soda_pugixml_candidates
  ${CMAKE_BINARY_DIR}/wasm-deps/usr/include/OpenImageIO/detail/pugixml
  /usr/include/OpenImageIO/detail/pugixml)
set(SODAEVO_PUGIXML_SOURCE_DIR "" CACHE PATH "Folder with pugixml.cpp for the WebAssembly build (empty: look in the usual places)")
set(_soda_pugixml_dir "${SODAEVO_PUGIXML_SOURCE_DIR}")
if(NOT _soda_pugixml_dir)
  foreach(dir ${_soda_pugixml_candidates})
    if(EXISTS ${dir}/pugixml.cpp)
      set(_soda_pugixml_dir ${dir})
      break()
    endif()
  endforeach()
endif()

set(SODAEVO_WASM_ENGINE "")
set(SODAEVO_WASM_EVOLVE "")
set(SODAEVO_WASM_MISSING "")
if(NOT SODAEVO_WASM)
  set(SODAEVO_WASM_MISSING "it was configured with -DSODAEVO_WASM=OFF")
elseif(NOT SODAEVO_EMXX)
  set(SODAEVO_WASM_MISSING "em++ was not found when it was configured (install Debian's emscripten: ./build.sh build does)")
elseif(NOT _soda_pugixml_dir)
  set(SODAEVO_WASM_MISSING "pugixml.cpp was not found when it was configured (./build.sh build unpacks it into ${CMAKE_BINARY_DIR}/wasm-deps)")
endif()

if(SODAEVO_WASM_MISSING)
  message(STATUS "sodaevo: WebAssembly engine not built: ${SODAEVO_WASM_MISSING}")
else()
  message(STATUS "sodaevo: WebAssembly engine with ${SODAEVO_EMXX}, pugixml from ${_soda_pugixml_dir}")
  set(SODAEVO_WASM_ENGINE ${CMAKE_BINARY_DIR}/web/soda_engine_wasm.js)
  # The evolution (web/evolve_api.cpp): evolve/ and the engine's fast stepper.
  set(SODAEVO_WASM_EVOLVE ${CMAKE_BINARY_DIR}/web/soda_evolve_wasm.js)
  file(GLOB_RECURSE _soda_wasm_inputs CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/core/*.cpp ${CMAKE_SOURCE_DIR}/core/*.hpp
       ${CMAKE_SOURCE_DIR}/formats/*.cpp ${CMAKE_SOURCE_DIR}/formats/*.hpp ${CMAKE_SOURCE_DIR}/evolve/*.cpp
       ${CMAKE_SOURCE_DIR}/evolve/*.hpp ${CMAKE_SOURCE_DIR}/web/*.cpp ${CMAKE_SOURCE_DIR}/web/*.hpp)
  add_custom_command(OUTPUT ${SODAEVO_WASM_ENGINE} ${SODAEVO_WASM_EVOLVE}
    COMMAND ${CMAKE_SOURCE_DIR}/web/build_wasm.sh ${CMAKE_BINARY_DIR}/web ${_soda_pugixml_dir}
    DEPENDS ${_soda_wasm_inputs} ${CMAKE_SOURCE_DIR}/web/build_wasm.sh
    COMMENT "WebAssembly engine (web/build_wasm.sh)" VERBATIM)
endif()

# The page's own files and the engine, as strings in the binary.
file(GLOB _soda_web_assets CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/web/*.js ${CMAKE_SOURCE_DIR}/web/*.html
     ${CMAKE_SOURCE_DIR}/web/*.css)
# The files the page bundles for Evolve mode: every file of models/ (seed models and
# terrains, byte for byte) and the run configs of configs/.
file(GLOB_RECURSE _soda_bundled CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/models/* ${CMAKE_SOURCE_DIR}/configs/*.json)
add_custom_command(OUTPUT ${CMAKE_BINARY_DIR}/generated/designer_assets.cpp
  COMMAND ${CMAKE_COMMAND} -DOUT=${CMAKE_BINARY_DIR}/generated/designer_assets.cpp "-DASSETS=${_soda_web_assets}"
          -DENGINE=${SODAEVO_WASM_ENGINE} -DEVOLVE=${SODAEVO_WASM_EVOLVE} "-DMISSING=${SODAEVO_WASM_MISSING}"
          -DROOT=${CMAKE_SOURCE_DIR} "-DBUNDLED=${_soda_bundled}" -P ${CMAKE_SOURCE_DIR}/web/embed_assets.cmake
  DEPENDS ${_soda_web_assets} ${_soda_bundled} ${SODAEVO_WASM_ENGINE} ${SODAEVO_WASM_EVOLVE} ${CMAKE_SOURCE_DIR}/web/embed_assets.cmake
  COMMENT "Designer page assets" VERBATIM)
target_sources(sodaevo_app PRIVATE ${CMAKE_BINARY_DIR}/generated/designer_assets.cpp)
