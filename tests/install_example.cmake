# Installs the build into WORK/prefix, builds examples/ against it and runs it; fails on any step
# or when the example's output misses the closed-form figures it prints.
file(REMOVE_RECURSE ${WORK})
function(step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed: ${ARGN}\n${out}\n${err}")
  endif()
  set(OUT "${out}" PARENT_SCOPE)
endfunction()
step(${CMAKE_COMMAND} --install ${BUILD} --prefix ${WORK}/prefix)
step(${CMAKE_COMMAND} -S ${SOURCE}/examples -B ${WORK}/build -DCMAKE_BUILD_TYPE=Release
     -DCMAKE_PREFIX_PATH=${WORK}/prefix)
step(${CMAKE_COMMAND} --build ${WORK}/build)
step(${WORK}/build/hello_world)
message(STATUS "${OUT}")
if(NOT OUT MATCHES "mass 350.0000 kg" OR NOT OUT MATCHES "centroid height 0.3750 m" OR
   NOT OUT MATCHES "t = 1.00 s: .*velocity z 1.6186 m/s")
  message(FATAL_ERROR "unexpected output of the installed example:\n${OUT}")
endif()
if(NOT EXISTS ${WORK}/prefix/bin/simreel)
  message(FATAL_ERROR "simreel was not installed")
endif()
