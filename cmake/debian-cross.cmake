# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# Toolchain for a cross build with Debian's cross compilers and multiarch libraries, for a
# Raspberry Pi (scripts/setup.sh --arch ARCH installs them; scripts/arm-test.sh uses this file):
#   cmake -DCMAKE_TOOLCHAIN_FILE=cmake/debian-cross.cmake -DBIRDCAGE_DEB_ARCH=arm64|armhf ...
# The ARM programs run on this machine under qemu-user (CMAKE_CROSSCOMPILING_EMULATOR), which is
# how ctest runs the tests and catch_discover_tests lists them; the ARM loader and libraries are
# the multiarch ones under /, so qemu's -L is /. The Debian package does not use this file:
# debhelper sets the same compilers (debian/rules adds the emulator).
set(CMAKE_TRY_COMPILE_PLATFORM_VARIABLES BIRDCAGE_DEB_ARCH)
if(BIRDCAGE_DEB_ARCH STREQUAL "arm64")
    set(triplet aarch64-linux-gnu)
    set(CMAKE_SYSTEM_PROCESSOR aarch64)
    set(qemu qemu-aarch64-static)
elseif(BIRDCAGE_DEB_ARCH STREQUAL "armhf")
    set(triplet arm-linux-gnueabihf)
    set(CMAKE_SYSTEM_PROCESSOR arm)
    set(qemu qemu-arm-static)
else()
    message(FATAL_ERROR "debian-cross.cmake: set BIRDCAGE_DEB_ARCH to arm64 or armhf (got '${BIRDCAGE_DEB_ARCH}')")
endif()
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_C_COMPILER ${triplet}-gcc)
set(CMAKE_CXX_COMPILER ${triplet}-g++)
set(CMAKE_LIBRARY_ARCHITECTURE ${triplet})
set(PKG_CONFIG_EXECUTABLE ${triplet}-pkg-config CACHE FILEPATH "pkg-config for ${BIRDCAGE_DEB_ARCH}")
set(CMAKE_CROSSCOMPILING_EMULATOR ${qemu} -L /)
set(CMAKE_CXX_FLAGS_INIT "-Wno-psabi")   # GCC notes that pair-passing changed in GCC 10: all of this is built by one compiler
