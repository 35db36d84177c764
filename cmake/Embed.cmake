# needlesim_embed_text(<input file> <C++ symbol> <output .cpp>)
# Writes a .cpp defining `const std::string_view needlesim::embedded::<symbol>`
# with the file's text, so the binary carries it (reports stay self-contained,
# the default scenario is the same text as its example file).
function(needlesim_embed_text input symbol output)
  file(READ ${input} _text)
  string(FIND "${_text}" ")NSJS\"" _clash)
  if(NOT _clash EQUAL -1)
    message(FATAL_ERROR "${input} contains the raw-string delimiter used by cmake/Embed.cmake")
  endif()
  string(LENGTH "${_text}" _len)
  set(_src "// Generated from ${input}. Do not edit.\n#include <string_view>\n")
  string(APPEND _src "namespace needlesim::embedded {\nstatic const char k${symbol}Data[] =\n")
  set(_pos 0)
  while(_pos LESS _len)
    string(SUBSTRING "${_text}" ${_pos} 16000 _chunk)
    string(APPEND _src "R\"NSJS(${_chunk})NSJS\"\n")
    math(EXPR _pos "${_pos} + 16000")
  endwhile()
  string(APPEND _src ";\nextern const std::string_view ${symbol};\n")
  string(APPEND _src "const std::string_view ${symbol}(k${symbol}Data, sizeof(k${symbol}Data) - 1);\n}\n")
  file(WRITE ${output}.in "${_src}")
  configure_file(${output}.in ${output} COPYONLY)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${input})
endfunction()

# Chart.js from Debian's libjs-chart.js (MIT licence): nothing is downloaded.
find_file(NEEDLESIM_CHARTJS chart.min.js PATHS /usr/share/javascript/chart.js NO_DEFAULT_PATH)
if(NOT NEEDLESIM_CHARTJS)
  message(FATAL_ERROR "Chart.js not found: run scripts/bootstrap.sh (Debian package libjs-chart.js)")
endif()
set(NEEDLESIM_CHARTJS_CPP ${CMAKE_BINARY_DIR}/generated/embedded_chartjs.cpp)
needlesim_embed_text(${NEEDLESIM_CHARTJS} kChartJs ${NEEDLESIM_CHARTJS_CPP})
set(NEEDLESIM_DEFAULT_SCENARIO_CPP ${CMAKE_BINARY_DIR}/generated/embedded_default_scenario.cpp)
needlesim_embed_text(${CMAKE_SOURCE_DIR}/examples/gelatin_18G_3mms.yaml kDefaultScenario
  ${NEEDLESIM_DEFAULT_SCENARIO_CPP})
# The publications "seed NNN" refers to: reports list those they cite (io/references).
set(NEEDLESIM_REFERENCES_CPP ${CMAKE_BINARY_DIR}/generated/embedded_references.cpp)
needlesim_embed_text(${CMAKE_SOURCE_DIR}/docs/references.md kReferences ${NEEDLESIM_REFERENCES_CPP})
# `needlesim serve`'s page (src/needlesim/live/web) with three.js and its orbit controls from
# Debian's libjs-three (MIT licence) and the Chart.js above: the page needs no network.
find_file(NEEDLESIM_THREEJS three.min.js PATHS /usr/share/javascript/three NO_DEFAULT_PATH)
find_file(NEEDLESIM_THREE_ORBIT OrbitControls.js PATHS /usr/share/javascript/three/examples/js/controls NO_DEFAULT_PATH)
if(NOT NEEDLESIM_THREEJS OR NOT NEEDLESIM_THREE_ORBIT)
  message(FATAL_ERROR "three.js not found: run scripts/bootstrap.sh (Debian package libjs-three)")
endif()
set(NEEDLESIM_WEB_CPP)
foreach(_pair "${NEEDLESIM_THREEJS}:kThreeJs" "${NEEDLESIM_THREE_ORBIT}:kThreeOrbitControls"
              "${CMAKE_SOURCE_DIR}/src/needlesim/live/web/index.html:kTrainerHtml"
              "${CMAKE_SOURCE_DIR}/src/needlesim/live/web/trainer.js:kTrainerJs")
  string(REPLACE ":" ";" _pair ${_pair})
  list(GET _pair 0 _file)
  list(GET _pair 1 _symbol)
  needlesim_embed_text(${_file} ${_symbol} ${CMAKE_BINARY_DIR}/generated/embedded_${_symbol}.cpp)
  list(APPEND NEEDLESIM_WEB_CPP ${CMAKE_BINARY_DIR}/generated/embedded_${_symbol}.cpp)
endforeach()
