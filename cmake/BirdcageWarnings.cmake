# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

# One place for the warning policy: -Wall -Wextra everywhere, -Werror when BIRDCAGE_WERROR is on (CI).
option(BIRDCAGE_WERROR "Treat warnings as errors" OFF)

function(birdcage_warnings target)
    target_compile_options(${target} PRIVATE
        -Wall -Wextra -Wshadow -Wcast-align -Wnull-dereference -Wdouble-promotion -Wformat=2
        -Wimplicit-fallthrough
        # C++ only: gcc warns about them on a C source (the backend's caps, src/hamlib/winegard.c).
        $<$<COMPILE_LANGUAGE:CXX>:-Wnon-virtual-dtor -Wold-style-cast -Woverloaded-virtual>)
    if(BIRDCAGE_WERROR)
        target_compile_options(${target} PRIVATE -Werror)
    endif()
endfunction()

# The libraries Hamlib's own tree builds (the core, the hazard rule, the rotctld client) stay within
# C++17, the newest standard Hamlib's build passes for this backend: a newer library feature fails
# to compile, a newer language feature GCC would accept as an extension warns (-Wpedantic).
function(birdcage_cxx17 target)
    set_target_properties(${target} PROPERTIES CXX_STANDARD 17 CXX_STANDARD_REQUIRED ON CXX_EXTENSIONS OFF)
    target_compile_options(${target} PRIVATE -Wpedantic)
endfunction()
