# The layering rule of docs/explanation/architecture.md: a stage never includes a later stage.
#
# gyrocomp_check_layers(<source dir> <stages in data-flow order>) reads every file under
# src/<stage>/ and include/gyrocomp/<stage>/, collects its `#include "gyrocomp/<other>/..."`
# lines and stops the configure step when <other> comes after <stage> in the list (or is not a
# stage at all, such as an old flat path "gyrocomp/vmd.h"). Tests and benchmarks follow the same
# rule as the code beside them, with one exception: they may include the simulator (stage "sim"),
# the source of ground truth for round-trip tests and benchmark inputs. Cheap: a few hundred file
# reads, no compilation.
#
# Also usable as a script: cmake -DSOURCE_DIR=<dir> -DSTAGES="core;io;..." -P check_layers.cmake
function(gyrocomp_check_layers source_dir stages)
  set(violations "")
  set(rank 0)
  foreach(stage IN LISTS stages)
    file(GLOB_RECURSE files
      "${source_dir}/src/${stage}/*.cc" "${source_dir}/src/${stage}/*.h"
      "${source_dir}/src/${stage}/*.inc" "${source_dir}/include/gyrocomp/${stage}/*.h")
    foreach(file IN LISTS files)
      file(STRINGS "${file}" includes REGEX "^[ \t]*#[ \t]*include[ \t]+\"gyrocomp/")
      foreach(line IN LISTS includes)
        string(REGEX MATCH "\"gyrocomp/([^\"]+)\"" _ "${line}")
        set(target "${CMAKE_MATCH_1}")
        string(REGEX MATCH "^([a-z_]+)/" _ "${target}")
        set(other "${CMAKE_MATCH_1}")
        list(FIND stages "${other}" other_rank)
        file(RELATIVE_PATH rel "${source_dir}" "${file}")
        if(other_rank EQUAL -1)
          string(APPEND violations "\n  ${rel}: includes gyrocomp/${target}, which is in no stage folder")
        elseif(other STREQUAL "sim" AND rel MATCHES "_(test|benchmark)\\.cc$")
          # allowed: tests and benchmarks draw their inputs from the simulator
        elseif(other_rank GREATER rank)
          string(APPEND violations
            "\n  ${rel}: stage '${stage}' includes gyrocomp/${target} of the later stage '${other}'")
        endif()
      endforeach()
    endforeach()
    math(EXPR rank "${rank} + 1")
  endforeach()
  if(violations)
    message(FATAL_ERROR "gyrocomp layering (stages in order: ${stages}):${violations}\n"
                        "Move the shared piece to the earlier stage, or the code to the later one.")
  endif()
endfunction()

if(CMAKE_SCRIPT_MODE_FILE AND DEFINED SOURCE_DIR)
  gyrocomp_check_layers("${SOURCE_DIR}" "${STAGES}")
endif()
