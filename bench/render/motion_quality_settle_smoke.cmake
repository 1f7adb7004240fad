# render_motion_quality --settle on a small Cornell box run: the settling table is printed with a
# column per checkpoint (the stop, 1, 2, 4 and 6 frames after it), its RMSEs are numbers in
# [0, 1], and holding the camera still improves the image (a settle that kept moving the camera,
# or rendered nothing new, would not) (docs/render.md, "Settling when the camera stops").
execute_process(COMMAND ${TOOL} --size 64 --frames 8 --spp 4 --runs path,still --settle 6 ${SCENE}
                OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "render_motion_quality failed (${rc}): ${err}")
endif()
set(n "([0-9]+\\.[0-9]+)")
string(REGEX MATCH "\\| cornell_box \\| epi, path \\| ${n} \\| ${n} \\| ${n} \\| ${n} \\| ${n} \\| ${n} \\| ([0-9]+|> 6) \\| ([0-9]+|> 6) \\|" row "${out}")
if(NOT row)
  message(FATAL_ERROR "no settling row in:\n${out}")
endif()
set(stop ${CMAKE_MATCH_1})
set(last ${CMAKE_MATCH_5})
set(still ${CMAKE_MATCH_6})
if(stop GREATER 1 OR still GREATER 1 OR NOT last LESS stop)
  message(FATAL_ERROR "implausible settling row (stop ${stop}, +6 ${last}, still ${still}):\n${out}")
endif()
