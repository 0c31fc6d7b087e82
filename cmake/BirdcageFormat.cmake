# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

# The build checks the one formatting style (.clang-format, applied by scripts/format.sh): with the
# tests on, in a git checkout, and where Debian 12's clang-format 14 is installed (scripts/test.sh
# installs it), a source file that differs from the style fails the build, naming the file. Other
# clang-format versions format some constructs differently, so the check is left out there and
# configure says so.
function(birdcage_format_check)
    if(NOT EXISTS ${PROJECT_SOURCE_DIR}/.git)
        return()
    endif()
    find_program(BIRDCAGE_CLANG_FORMAT NAMES clang-format-14 clang-format)
    if(NOT BIRDCAGE_CLANG_FORMAT)
        message(STATUS "format check: off (clang-format 14 not found; scripts/test.sh installs it)")
        return()
    endif()
    execute_process(COMMAND ${BIRDCAGE_CLANG_FORMAT} --version OUTPUT_VARIABLE _version)
    if(NOT _version MATCHES "version 14\\.")
        message(STATUS "format check: off (${BIRDCAGE_CLANG_FORMAT} is not version 14)")
        return()
    endif()
    file(GLOB_RECURSE _sources CONFIGURE_DEPENDS
        ${PROJECT_SOURCE_DIR}/src/*.cpp ${PROJECT_SOURCE_DIR}/src/*.hpp ${PROJECT_SOURCE_DIR}/src/*.h
        ${PROJECT_SOURCE_DIR}/src/*.c ${PROJECT_SOURCE_DIR}/sim/*.cpp ${PROJECT_SOURCE_DIR}/sim/*.hpp
        ${PROJECT_SOURCE_DIR}/tools/*.cpp ${PROJECT_SOURCE_DIR}/tools/*.hpp ${PROJECT_SOURCE_DIR}/tui/*.cpp
        ${PROJECT_SOURCE_DIR}/tui/*.hpp ${PROJECT_SOURCE_DIR}/testbed/*.cpp ${PROJECT_SOURCE_DIR}/testbed/*.hpp
        ${PROJECT_SOURCE_DIR}/bench/*.cpp ${PROJECT_SOURCE_DIR}/tests/*.cpp ${PROJECT_SOURCE_DIR}/tests/*.hpp
        ${PROJECT_SOURCE_DIR}/upstream/*.c ${PROJECT_SOURCE_DIR}/upstream/*.h)
    set(_stamp ${CMAKE_BINARY_DIR}/format-check.stamp)
    add_custom_command(OUTPUT ${_stamp}
        COMMAND ${CMAKE_COMMAND} -E env CLANG_FORMAT=${BIRDCAGE_CLANG_FORMAT}
                bash ${PROJECT_SOURCE_DIR}/scripts/format.sh --check
        COMMAND ${CMAKE_COMMAND} -E touch ${_stamp}
        DEPENDS ${_sources} ${PROJECT_SOURCE_DIR}/.clang-format
        WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
        COMMENT "format check (.clang-format; scripts/format.sh fixes)"
        VERBATIM)
    add_custom_target(format_check ALL DEPENDS ${_stamp})
endfunction()
