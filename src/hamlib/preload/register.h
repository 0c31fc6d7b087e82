/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* Copyright (C) 2026 the birdcage authors */

/* What the caps file (src/hamlib/caps/winegard.c) takes from Hamlib's private src/register.h, for
 * the preload build, which compiles it against an installed Hamlib: the versioned entry point
 * (ABI 4 names it initrots4_winegard; the preload build refuses any other ABI). The model numbers
 * rotlist.h would give come from winegard_rotlist.h, which the build generates from
 * src/hamlib/rotlist.h.in with the preload family (BIRDCAGE_MODEL_FAMILY) and includes in
 * every source of the library. */
#ifndef BIRDCAGE_PRELOAD_REGISTER_H
#define BIRDCAGE_PRELOAD_REGISTER_H

#define DECLARE_INITROT_BACKEND(backend)                                             \
    __attribute__((visibility("default"))) int initrots4_##backend(void* be_handle); \
    int initrots4_##backend(void* be_handle __attribute__((unused)))

#endif
