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
# Boxes at rest: the contact read-out carries each box's weight (the program checks it, exit 1).
step(${WORK}/build/resting_boxes)
message(STATUS "${OUT}")
if(NOT OUT MATCHES "box 0: mass 4.000 kg, weight 39.240 N, ground pushes 39.240 N up" OR
   NOT OUT MATCHES "every box rests on its weight")
  message(FATAL_ERROR "unexpected output of the installed example:\n${OUT}")
endif()
# Only the public headers are installed: <simreel/...>, nothing of sim/.
file(GLOB_RECURSE installed_headers RELATIVE ${WORK}/prefix/include ${WORK}/prefix/include/*)
foreach(h ${installed_headers})
  if(NOT h MATCHES "^simreel/[a-z_]+\\.hpp$")
    message(FATAL_ERROR "a private header was installed: ${h}")
  endif()
endforeach()
if(NOT EXISTS ${WORK}/prefix/include/simreel/simreel.hpp)
  message(FATAL_ERROR "simreel/simreel.hpp was not installed")
endif()
if(NOT EXISTS ${WORK}/prefix/bin/simreel)
  message(FATAL_ERROR "simreel was not installed")
endif()
# The Python package, where it was built: under PREFIX/lib/python3/dist-packages, importable from
# there and nowhere else (PYTHONPATH is the installed folder, not the build's).
if(PYTHON)
  if(NOT EXISTS ${WORK}/prefix/lib/python3/dist-packages/simreel/__init__.py)
    message(FATAL_ERROR "the Python package was not installed under PREFIX/lib/python3/dist-packages")
  endif()
  # (a file: the code's line breaks would otherwise be CMake list separators)
  file(WRITE ${WORK}/installed.py "import simreel\n"
       "sim = simreel.Scene('x').add_body('b', shape='sphere', radius=0.1).build()\n"
       "sim.step(240)\n"
       "print(simreel.__file__, sim.time, sim.positions[0][2])\n")
  step(${CMAKE_COMMAND} -E env PYTHONPATH=${WORK}/prefix/lib/python3/dist-packages ${PYTHON} ${WORK}/installed.py)
  message(STATUS "${OUT}")
  if(NOT OUT MATCHES "^${WORK}/prefix/lib/python3/dist-packages/simreel/__init__.py 1.0 ")
    message(FATAL_ERROR "the installed Python package did not run as expected:\n${OUT}")
  endif()
endif()
