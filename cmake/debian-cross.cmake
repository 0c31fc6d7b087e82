# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# Toolchain for a cross build for a Raspberry Pi with Debian's cross compilers
# (crossbuild-essential-ARCH, scripts/setup.sh --arch) against a sysroot: Debian 12's own ARCH
# packages of the libraries, unpacked into a directory, not installed (scripts/lib.sh's
# debian_root; scripts/arm-test.sh and scripts/package.sh make it):
#   cmake -DCMAKE_TOOLCHAIN_FILE=cmake/debian-cross.cmake -DBIRDCAGE_DEB_ARCH=arm64|armhf \
#         -DBIRDCAGE_SYSROOT=<the unpacked root> ...
# The compiler keeps its own libc (/usr/<triplet>, the same glibc release as the sysroot's); the
# headers, libraries, pkg-config files and Catch2 come from the sysroot, and the libraries those
# libraries need are resolved there at link time (-rpath-link). The ARM programs run on this
# machine under qemu-user with the sysroot as its root (-L: the ARM loader and libraries are the
# sysroot's), which is how ctest runs the tests, catch_discover_tests lists them and help2man
# reads their --help. debian/rules uses this file for a package built against a sysroot.
set(CMAKE_TRY_COMPILE_PLATFORM_VARIABLES BIRDCAGE_DEB_ARCH BIRDCAGE_SYSROOT)
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
if(NOT IS_DIRECTORY "${BIRDCAGE_SYSROOT}/usr/lib/${triplet}")
    message(FATAL_ERROR "debian-cross.cmake: set BIRDCAGE_SYSROOT to the unpacked ${BIRDCAGE_DEB_ARCH} packages "
                        "(got '${BIRDCAGE_SYSROOT}', which has no usr/lib/${triplet})")
endif()
set(sysroot "${BIRDCAGE_SYSROOT}")
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_C_COMPILER ${triplet}-gcc)
set(CMAKE_CXX_COMPILER ${triplet}-g++)
set(CMAKE_LIBRARY_ARCHITECTURE ${triplet})

# Libraries, headers and CMake packages from the sysroot only; programs (pkg-config, python3,
# help2man) from this machine.
set(CMAKE_FIND_ROOT_PATH "${sysroot}")
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
# This machine's pkg-config reads the sysroot's .pc files only and prefixes their paths with it.
# FORCE: debhelper passes the multiarch <triplet>-pkg-config, which reads the host's instead.
set(PKG_CONFIG_EXECUTABLE pkg-config CACHE FILEPATH "pkg-config, reading ${sysroot}" FORCE)
set(ENV{PKG_CONFIG_LIBDIR} "${sysroot}/usr/lib/${triplet}/pkgconfig:${sysroot}/usr/share/pkgconfig")
set(ENV{PKG_CONFIG_SYSROOT_DIR} "${sysroot}")
unset(ENV{PKG_CONFIG_PATH})
# Debian 12's libraries are in lib/<triplet> and usr/lib/<triplet>: -L for the linker scripts'
# INPUT (libncurses.so names libncurses.so.6), -rpath-link for the libraries' own dependencies.
foreach(kind EXE SHARED MODULE)
    set(CMAKE_${kind}_LINKER_FLAGS_INIT "-L${sysroot}/usr/lib/${triplet} -L${sysroot}/lib/${triplet} \
-Wl,-rpath-link,${sysroot}/usr/lib/${triplet}:${sysroot}/lib/${triplet}")
endforeach()

set(CMAKE_CROSSCOMPILING_EMULATOR ${qemu} -L "${sysroot}")
set(CMAKE_CXX_FLAGS_INIT "-Wno-psabi")   # GCC notes that pair-passing changed in GCC 10: all of this is built by one compiler
