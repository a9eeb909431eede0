# No file of the repository may name an absolute path of one machine (a home, work, root or temporary
# directory): users do not have it. Run as a ctest test (see tests/CMakeLists.txt):
#
#   cmake -DSOURCE_DIR=<repository root> -P check_no_absolute_paths.cmake
#       Scans the repository's files: `git ls-files --cached --others --exclude-standard` (tracked files plus new,
#       not ignored ones) when SOURCE_DIR is a git checkout and git is available, else every file under SOURCE_DIR
#       except build*/, out/ and .git/. Fails listing file:line: text for every hit.
#   cmake -DSELF_TEST=ON -DWORK_DIR=<scratch dir> -P check_no_absolute_paths.cmake
#       Plants files with and without such paths in WORK_DIR (not a git checkout, so the glob mode runs) and
#       fails unless exactly the planted paths are flagged.
#
# A hit is one of the directories below, written with a leading and a trailing slash, at the start of a line or
# after a character that cannot be part of a relative path or an identifier (so `./work/x`, `foo/home/x` and
# `/usr/include` pass). This includes the project's stop-hook check, which greps for the first three names with
# `(^|[^A-Za-z0-9_.])` in front.
cmake_minimum_required(VERSION 3.20)

set(_dirs work root home tmp Users)  # Users: the macOS home directories
string(JOIN "|" _alt ${_dirs})
set(_pattern "(^|[^A-Za-z0-9_.])/(${_alt})/")

# Appends a line "  file:line: text" to the string `out` for each hit in `file` (relative to `root`) and counts the
# hits in `out_n`. (A string, not a list: the hit lines may contain `;`.)
function(_scan_file root file out)
  set(hits "${${out}}")
  set(hits_n ${${out}_n})
  if(IS_DIRECTORY "${root}/${file}" OR NOT EXISTS "${root}/${file}")
    return()  # e.g. a tracked file deleted in the working tree, or a submodule
  endif()
  file(READ "${root}/${file}" content)
  # Whole-file test first: a newline is a non-identifier character, so line starts are covered.
  if(NOT content MATCHES "${_pattern}")
    return()
  endif()
  # Split into lines for the line numbers. `;`, `[` and `]` would break CMake's list splitting: swap them for
  # control characters (still non-identifier characters for the pattern) and back for the message.
  string(ASCII 1 semi)
  string(ASCII 2 open)
  string(ASCII 3 close)
  string(REPLACE ";" "${semi}" content "${content}")
  string(REPLACE "[" "${open}" content "${content}")
  string(REPLACE "]" "${close}" content "${content}")
  string(REPLACE "\n" ";" lines "${content}")
  set(n 0)
  foreach(line IN LISTS lines)
    math(EXPR n "${n} + 1")
    if(line MATCHES "${_pattern}")
      string(REPLACE "${semi}" ";" line "${line}")
      string(REPLACE "${open}" "[" line "${line}")
      string(REPLACE "${close}" "]" line "${line}")
      string(STRIP "${line}" line)
      string(APPEND hits "\n  ${file}:${n}: ${line}")
      math(EXPR hits_n "${hits_n} + 1")
    endif()
  endforeach()
  set(${out} "${hits}" PARENT_SCOPE)
  set(${out}_n ${hits_n} PARENT_SCOPE)
endfunction()

# Sets `out` to the files to scan under `root`, relative to it.
function(_list_files root out)
  set(files "")
  find_program(_git git)
  if(_git AND EXISTS "${root}/.git")
    execute_process(COMMAND "${_git}" -c core.quotePath=false ls-files --cached --others --exclude-standard
                    WORKING_DIRECTORY "${root}" OUTPUT_VARIABLE listing RESULT_VARIABLE rc ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "git ls-files failed in ${root}: ${err}")
    endif()
    string(REPLACE ";" "\\;" listing "${listing}")
    string(REPLACE "\n" ";" files "${listing}")
    message(STATUS "scanning the git-listed files of ${root}")
  else()
    file(GLOB_RECURSE all LIST_DIRECTORIES false RELATIVE "${root}" "${root}/*")
    foreach(f IN LISTS all)
      if(NOT f MATCHES "^(build[^/]*|out|\\.git)/")
        list(APPEND files "${f}")
      endif()
    endforeach()
    message(STATUS "scanning every file under ${root} except build*/, out/, .git/ (not a git checkout)")
  endif()
  list(REMOVE_DUPLICATES files)
  list(REMOVE_ITEM files "")
  set(${out} ${files} PARENT_SCOPE)
endfunction()

function(_scan_tree root out)
  _list_files("${root}" files)
  list(LENGTH files count)
  set(hits "")
  set(hits_n 0)
  foreach(f IN LISTS files)
    _scan_file("${root}" "${f}" hits)
  endforeach()
  set(${out} "${hits}" PARENT_SCOPE)
  set(${out}_n ${hits_n} PARENT_SCOPE)
  set(${out}_count ${count} PARENT_SCOPE)
endfunction()

if(SELF_TEST)
  if(NOT WORK_DIR)
    message(FATAL_ERROR "SELF_TEST needs -DWORK_DIR=<scratch directory>")
  endif()
  set(dir "${WORK_DIR}/absolute_path_self_test")
  file(REMOVE_RECURSE "${dir}")
  # The planted paths are assembled here so that this file itself names none.
  set(s "/")
  set(bad
      "see ${s}work${s}shared/robots.md"
      "${s}home${s}alice/rome/robots"
      "path: '${s}root${s}.cache/x'"
      "x=\"${s}tmp${s}out.csv\""
      "<!-- from ${s}Users${s}bob/notes -->"
      "(${s}work${s}a)")
  set(good
      "#include </usr/include/eigen3/Eigen/Core>"
      "cd ./work/dir && ../home/x"
      "robots/home/amber.urdf and some_tmp/file"
      "https://example.org/docs/tmp_files/"
      "a /worker/ or /homes/ or /tmpfs/ is another directory"
      "std::filesystem::temp_directory_path() / \"rome\"")
  string(JOIN "\n" bad_text ${bad})
  string(JOIN "\n" good_text ${good})
  file(WRITE "${dir}/docs/bad.md" "first line\n${bad_text}\n")
  file(WRITE "${dir}/good.cc" "${good_text}\n")
  file(WRITE "${dir}/build-x/ignored.txt" "${s}home${s}ignored/in/build/dir\n")
  _scan_tree("${dir}" hits)
  list(LENGTH bad expected)
  message(STATUS "flagged:${hits}")
  set(expected_hits "")
  foreach(i RANGE 2 7)
    string(APPEND expected_hits "\n  docs/bad.md:${i}: ")
  endforeach()
  string(REGEX REPLACE ": [^\n]*" ": " hit_locations "${hits}")
  if(NOT hits_n EQUAL expected OR NOT hits_count EQUAL 2 OR NOT hit_locations STREQUAL expected_hits)
    message(FATAL_ERROR "self test: expected ${expected} hits (docs/bad.md lines 2-7) in 2 scanned files, got ${hits_n} "
                        "hits in ${hits_count} files:${hits}")
  endif()
  file(REMOVE_RECURSE "${dir}")
  message(STATUS "self test passed: ${hits_n} planted paths flagged, no legitimate string flagged")
  return()
endif()

if(NOT SOURCE_DIR)
  message(FATAL_ERROR "usage: cmake -DSOURCE_DIR=<repository root> -P check_no_absolute_paths.cmake")
endif()
_scan_tree("${SOURCE_DIR}" hits)
if(hits_n GREATER 0)
  message(FATAL_ERROR "${hits_n} line(s) name an absolute path of one machine (users do not have it; cite the source "
                      "list in robots/README.md or use a path relative to the repository):${hits}")
endif()
message(STATUS "no absolute machine paths in ${hits_count} files")
