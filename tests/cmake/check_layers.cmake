# Fails when a file includes a part above its own. The order of the parts is
# read from the table under "## Layout" in docs/architecture.md (each row a
# `src/<part>/` folder; each part may include only itself and the rows above
# it), so the check and the page cannot drift apart.
#   -DROOT=dir   the tree to check: its src/<part>/ and include/pbf/<part>/
#   -DDOC=file   the page holding the table
# A file of src/<part>/ or include/pbf/<part>/ belongs to <part>; an include
# "<part>/..." or <pbf/<part>/...> names the part it reaches.
cmake_minimum_required(VERSION 3.25)
get_filename_component(ROOT "${ROOT}" ABSOLUTE)
file(STRINGS "${DOC}" rows REGEX "^\\| `src/[a-z_]+/` \\|")
set(order)
foreach(row IN LISTS rows)
  string(REGEX REPLACE "^\\| `src/([a-z_]+)/`.*" "\\1" part "${row}")
  list(APPEND order ${part})
endforeach()
list(LENGTH order count)
if(count LESS 5)
  message(FATAL_ERROR "${DOC}: found ${count} layers in the Layout table, expected the src/ parts")
endif()
message("layers, lowest first: ${order}")

set(problems 0)
foreach(part IN LISTS order)
  list(FIND order ${part} own)
  file(GLOB_RECURSE files LIST_DIRECTORIES false
       "${ROOT}/src/${part}/*.hpp" "${ROOT}/src/${part}/*.cpp" "${ROOT}/src/${part}/*.h"
       "${ROOT}/src/${part}/*.cu" "${ROOT}/src/${part}/*.cuh"
       "${ROOT}/include/pbf/${part}/*.hpp" "${ROOT}/include/pbf/${part}/*.h")
  foreach(file IN LISTS files)
    file(STRINGS "${file}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"]")
    foreach(line IN LISTS includes)
      if(NOT line MATCHES "include[ \t]*[<\"](pbf/)?([a-z_]+)/")
        continue()
      endif()
      set(target ${CMAKE_MATCH_2})
      list(FIND order ${target} rank)
      if(rank GREATER own)
        file(RELATIVE_PATH rel "${ROOT}" "${file}")
        string(STRIP "${line}" line)
        message("${rel}: part ${part} includes ${target}, a part above it: ${line}")
        math(EXPR problems "${problems} + 1")
      endif()
    endforeach()
  endforeach()
endforeach()
if(problems GREATER 0)
  message(FATAL_ERROR "${problems} upward include(s); the layer order is the Layout table of ${DOC}")
endif()
message("no file includes a part above its own")
