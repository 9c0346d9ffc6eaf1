# Run at build time (cmake -P) once zbrdf is built: makes the shell completion scripts and, with
# help2man, the man pages, all from the binary itself, so that they list exactly its commands and
# flags. Called by the zbrdf_docs target (CMakeLists.txt, Install):
#   cmake -DZBRDF=build/zbrdf -DOUT=build/docs [-DHELP2MAN=/usr/bin/help2man] -P ZbrdfDocs.cmake
# Writes OUT/completions/zbrdf (bash), OUT/completions/_zbrdf (zsh), OUT/man1/zbrdf.1 (the
# command list) and OUT/man1/zbrdf-<command>[-<action>].1, one page per command and action (as git
# does: `man zbrdf-simulate` finds a command's flags without paging through every other command).

function(run_zbrdf out_file)
  execute_process(COMMAND "${ZBRDF}" ${ARGN} OUTPUT_FILE "${out_file}" RESULT_VARIABLE rc
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "zbrdf ${ARGN} failed (${rc}): ${err}")
  endif()
endfunction()

file(MAKE_DIRECTORY "${OUT}/completions")
run_zbrdf("${OUT}/completions/zbrdf" completion bash)
run_zbrdf("${OUT}/completions/_zbrdf" completion zsh)

# Pages of commands that no longer exist must not be installed: start from an empty folder.
file(REMOVE_RECURSE "${OUT}/man1")
if(NOT HELP2MAN)
  return()
endif()
file(MAKE_DIRECTORY "${OUT}/man1")
run_zbrdf("${OUT}/commands.txt" completion commands)
execute_process(COMMAND "${ZBRDF}" version OUTPUT_VARIABLE version_line
                OUTPUT_STRIP_TRAILING_WHITESPACE)
string(REGEX REPLACE "^zbrdf " "" version "${version_line}")
# One line per command or action, WORDS<tab>SUMMARY. A summary may hold ';', CMake's list
# separator: stand it in while the lines are a list.
file(READ "${OUT}/commands.txt" text)
string(REPLACE ";" "<semicolon>" text "${text}")
string(STRIP "${text}" text)
string(REPLACE "\n" ";" lines "${text}")

function(help2man page name_line include_file)
  execute_process(COMMAND "${HELP2MAN}" --no-info --name "${name_line}" --include "${include_file}"
                          --output "${OUT}/man1/${page}.1" ${ARGN} "${ZBRDF}"
                  RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "help2man for ${page} failed (${rc}): ${err}")
  endif()
endfunction()

set(see_also "")
file(WRITE "${OUT}/see-zbrdf.h2m" "[SEE ALSO]\n.BR zbrdf (1)\n")
foreach(line IN LISTS lines)
  if(NOT line MATCHES "^([^\t]+)\t(.*)$")
    message(FATAL_ERROR "zbrdf completion commands: unexpected line '${line}'")
  endif()
  set(words "${CMAKE_MATCH_1}")
  string(REPLACE "<semicolon>" ";" summary "${CMAKE_MATCH_2}")
  string(REPLACE " " "-" page "zbrdf-${words}")
  # --version-string names the page (help2man takes the program name from it); the help text is
  # `zbrdf WORDS --help`, which help2man runs through the shell.
  help2man("${page}" "${summary}" "${OUT}/see-zbrdf.h2m" --version-string "${page} ${version}"
           --help-option "${words} --help")
  string(APPEND see_also ",\n.BR ${page} (1)")
endforeach()
string(SUBSTRING "${see_also}" 2 -1 see_also)
file(WRITE "${OUT}/see-commands.h2m" "[SEE ALSO]\n${see_also}\n")
help2man(zbrdf "measure, simulate, fit and export BRDFs captured with zonal basis illumination"
         "${OUT}/see-commands.h2m")
file(REMOVE "${OUT}/commands.txt" "${OUT}/see-zbrdf.h2m" "${OUT}/see-commands.h2m")
