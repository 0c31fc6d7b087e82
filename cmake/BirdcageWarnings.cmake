# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

# One place for the warning policy: -Wall -Wextra everywhere, -Werror when BIRDCAGE_WERROR is on (CI).
option(BIRDCAGE_WERROR "Treat warnings as errors" OFF)

function(birdcage_warnings target)
    target_compile_options(${target} PRIVATE
        -Wall -Wextra -Wshadow -Wnon-virtual-dtor -Wold-style-cast -Wcast-align
        -Woverloaded-virtual -Wnull-dereference -Wdouble-promotion -Wformat=2
        -Wimplicit-fallthrough)
    if(BIRDCAGE_WERROR)
        target_compile_options(${target} PRIVATE -Werror)
    endif()
endfunction()
