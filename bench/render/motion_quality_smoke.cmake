# render_motion_quality --colours on a small Cornell box run: the second table is printed, it
# compared a few hundred drawn points (a lookup that matched no surface would compare none), and
# its causes add up to no more than the points off (docs/render.md, "Diffuse transmission").
execute_process(COMMAND ${TOOL} --size 64 --frames 8 --spp 4 --runs path --colours ${SCENE}
                OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "render_motion_quality failed (${rc}): ${err}")
endif()
string(REGEX MATCH "\\| cornell_box \\| epi, path \\| ([0-9]+) \\| ([0-9]+) \\([^)]*\\) \\| ([0-9]+) \\([^)]*\\) \\| ([0-9]+) \\([^)]*\\) \\| ([0-9]+) " row "${out}")
if(NOT row)
  message(FATAL_ERROR "no --colours row in:\n${out}")
endif()
set(compared ${CMAKE_MATCH_1})
set(off ${CMAKE_MATCH_2})
math(EXPR causes "${CMAKE_MATCH_3} + ${CMAKE_MATCH_4} + ${CMAKE_MATCH_5}")
if(compared LESS 100 OR off GREATER compared OR NOT causes EQUAL off)
  message(FATAL_ERROR "implausible --colours row (compared ${compared}, off ${off}, causes ${causes}):\n${out}")
endif()
