# Every file of the package's source folders must appear in a list of CMakeLists.txt, so that a
# new source, test, message or script cannot be silently left out of the build, the tests, the
# install rules or the --help check.
#
# Folders checked: src/, test/ (except test/data/), msg/, srv/, scripts/.
#
# Two uses of this file:
#  - include()d by CMakeLists.txt: surgical_sim_check_source_lists(<file> ...) stops the configure
#    step with an error naming every unlisted file, and records the list in
#    ${CMAKE_BINARY_DIR}/surgical_sim_listed_files.txt for the test below;
#  - script mode, the catkin test "source_lists" (a file added after the last configure):
#      cmake -DSOURCE_DIR=<repo> -DLISTED=<listed_files.txt> [-DXML=<junit.xml>]
#            -P check_source_lists.cmake
#    fails naming every unlisted file (and writes a one-case JUnit file when XML is given).

# Sets ${out} to the files (relative to source_dir) of the checked folders that are not in listed.
function(_surgical_sim_unlisted_files source_dir listed out)
  file(GLOB_RECURSE present RELATIVE ${source_dir}
       ${source_dir}/src/* ${source_dir}/test/* ${source_dir}/msg/* ${source_dir}/srv/*
       ${source_dir}/scripts/*)
  set(missing)
  foreach(f ${present})
    if(f MATCHES "^test/data/" OR f MATCHES "(/__pycache__/|\\.pyc$)")
      continue()
    endif()
    list(FIND listed ${f} index)
    if(index EQUAL -1)
      list(APPEND missing ${f})
    endif()
  endforeach()
  list(SORT missing)
  set(${out} "${missing}" PARENT_SCOPE)
endfunction()

function(_surgical_sim_unlisted_message missing out)
  string(REPLACE ";" "\n  " lines "${missing}")
  set(${out}
      "files in no list of CMakeLists.txt (add each to its list, alphabetically):\n  ${lines}"
      PARENT_SCOPE)
endfunction()

if(CMAKE_SCRIPT_MODE_FILE)
  file(STRINGS ${LISTED} listed)
  _surgical_sim_unlisted_files(${SOURCE_DIR} "${listed}" missing)
  if(missing)
    _surgical_sim_unlisted_message("${missing}" message)
  endif()
  if(XML)
    get_filename_component(xml_dir ${XML} DIRECTORY)
    file(MAKE_DIRECTORY ${xml_dir})
    set(failure "")
    set(failures 0)
    if(missing)
      string(REPLACE ";" " " names "${missing}")
      set(failure "    <failure message=\"not in any list of CMakeLists.txt: ${names}\"/>\n")
      set(failures 1)
    endif()
    file(WRITE ${XML}
         "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<testsuite name=\"source_lists\" tests=\"1\" failures=\"${failures}\" errors=\"0\">\n"
         "  <testcase classname=\"source_lists\" name=\"every_file_listed\">\n${failure}"
         "  </testcase>\n</testsuite>\n")
  endif()
  if(missing)
    message(FATAL_ERROR "${message}")
  endif()
  message(STATUS "source lists OK: every file of src/ test/ msg/ srv/ scripts/ is listed")
  return()
endif()

function(surgical_sim_check_source_lists)
  set(listed ${ARGN})
  string(REPLACE ";" "\n" text "${listed}")
  file(WRITE ${CMAKE_BINARY_DIR}/surgical_sim_listed_files.txt "${text}\n")
  _surgical_sim_unlisted_files(${CMAKE_CURRENT_SOURCE_DIR} "${listed}" missing)
  if(missing)
    _surgical_sim_unlisted_message("${missing}" message)
    message(FATAL_ERROR "${message}")
  endif()
endfunction()
