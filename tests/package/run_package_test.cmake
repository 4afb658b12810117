# ctest case package_example: installs the built project into a fresh prefix (cmake --install,
# nothing is rebuilt), configures and builds tests/package against it with find_package(Extremal)
# alone, runs the example on a STEP box and checks the distances it prints.
# Variables: BUILD_DIR, SOURCE_DIR, WORK_DIR, PART, GENERATOR, CXX_COMPILER, BUILD_TYPE, LAUNCHER,
# SANITIZE (the build's EXTREMAL_SANITIZE: the example must then compile and link with the
# sanitizers, through the package alone; otherwise with none).
foreach(var BUILD_DIR SOURCE_DIR WORK_DIR PART GENERATOR CXX_COMPILER SANITIZE)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_package_test.cmake: ${var} not set")
  endif()
endforeach()

function(run step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${step} failed (${rc}):\n${ARGN}\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

set(prefix "${WORK_DIR}/prefix")
set(example_build "${WORK_DIR}/build")
file(REMOVE_RECURSE "${WORK_DIR}")

run("install" ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}")
foreach(installed include/extremal/Extremal.h include/extremal/kernel/Body.h
                  include/extremal/io/Model_reader.h include/extremal/algorithms/Scene_stepper.h
                  lib/cmake/Extremal/ExtremalConfig.cmake
                  lib/cmake/Extremal/ExtremalConfigVersion.cmake)
  if(NOT EXISTS "${prefix}/${installed}")
    message(FATAL_ERROR "install: ${prefix}/${installed} missing")
  endif()
endforeach()
if(EXISTS "${prefix}/include/extremal/kernel/internal")
  message(FATAL_ERROR "install: internal headers were installed")
endif()

set(launcher)
if(LAUNCHER)
  set(launcher "-DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER}")
endif()
run("configure the example" ${CMAKE_COMMAND} -S "${SOURCE_DIR}/tests/package"
    -B "${example_build}" -G "${GENERATOR}" "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}"
    "-DCMAKE_BUILD_TYPE=${BUILD_TYPE}" "-DCMAKE_PREFIX_PATH=${prefix}"
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_EXPORT_COMPILE_COMMANDS=ON ${launcher})
# The package found must be the one just installed, not a source or build tree.
if(NOT run_output MATCHES "Extremal 0\\.1\\.[0-9]+ from ${prefix}/lib/cmake/Extremal")
  message(FATAL_ERROR "the example did not find the installed package:\n${run_output}")
endif()
# A sanitized install hands its sanitizer options to the consumer (Extremal::sanitizers); a plain
# one hands over none.
file(READ "${example_build}/compile_commands.json" compile_commands)
foreach(flag "-fsanitize=address,undefined" "-fno-sanitize-recover=all")
  string(FIND "${compile_commands}" "${flag}" at)
  if(SANITIZE AND at EQUAL -1)
    message(FATAL_ERROR "sanitized install: the example is compiled without ${flag}:\n${compile_commands}")
  elseif(NOT SANITIZE AND NOT at EQUAL -1)
    message(FATAL_ERROR "plain install: the example is compiled with ${flag}:\n${compile_commands}")
  endif()
endforeach()
run("build the example" ${CMAKE_COMMAND} --build "${example_build}")
run("run the example" "${example_build}/extremal_example" "${PART}" 2)
message(STATUS "${run_output}")

# PART is pr2ct.stp, the cube [0, 200]^3 mm: the sphere (radius 20) runs along x = -100 + 400 t
# at y = 100, z = 222. Over the top (0 <= x <= 200, t in [0.25, 0.75]) the distance is the
# clearance, 2; elsewhere the nearest point is a top edge: sqrt((x - edge)^2 + 22^2) - 20,
# i.e. 82.391406 at t = 0 and t = 1, 9.732137 at t = 0.2 and t = 0.8.
foreach(expected "t 0\\.00  distance 82\\.39140[56] mm" "t 0\\.20  distance 9\\.73213[67] mm"
                 "t 0\\.50  distance 2\\.000000 mm" "t 0\\.80  distance 9\\.73213[67] mm"
                 "t 1\\.00  distance 82\\.39140[56] mm" "closest 2\\.000000 mm at t 0\\.2[5-9]")
  if(NOT run_output MATCHES "${expected}")
    message(FATAL_ERROR "the example's output does not match ${expected}")
  endif()
endforeach()
