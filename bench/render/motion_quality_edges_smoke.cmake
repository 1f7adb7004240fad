# render_motion_quality --edges on a small torus_capsule run: the column is printed for both runs,
# the path (the torus sweeping over the capsule, sparsely sampled in motion) draws a share of its
# edges behind nearer surfaces, and the still view, whose cloud fills in, draws a smaller one
# (docs/render.md, "Edges behind nearer surfaces"). A comparison the wrong way round, or depths
# taken as their inverses, gives shares near 0 or 100 %.
execute_process(COMMAND ${TOOL} --size 96 --frames 30 --spp 4 --runs path,still --edges ${SCENE}
                OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "render_motion_quality failed (${rc}): ${err}")
endif()
foreach(run path still)
  string(REGEX MATCH "\\| torus_capsule \\| epi, ${run} \\|[^\n]* ([0-9.]+) % \\|\n" row "${out}")
  if(NOT row)
    message(FATAL_ERROR "no --edges column in the ${run} row:\n${out}")
  endif()
  set(${run} ${CMAKE_MATCH_1})
endforeach()
if(path LESS 5 OR path GREATER 40 OR NOT still LESS path)
  message(FATAL_ERROR "implausible edges behind (path ${path} %, still ${still} %):\n${out}")
endif()
