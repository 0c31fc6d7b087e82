# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

# BIRDCAGE_SANITIZE=ON builds everything with AddressSanitizer and UndefinedBehaviorSanitizer.
option(BIRDCAGE_SANITIZE "Build with -fsanitize=address,undefined" OFF)
if(BIRDCAGE_SANITIZE)
    add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
    add_link_options(-fsanitize=address,undefined)
endif()
