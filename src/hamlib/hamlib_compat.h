// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

/* Hides the Hamlib API differences between 4.5.4 (Debian bookworm) and 4.6 / 4.7 / master (C++ only).
 * Never touch rot->state directly: Hamlib master moved the rotator state behind accessor macros
 * (HAMLIB_ROTSTATE/HAMLIB_ROTPORT, 4.7+), so a backend that dereferences rot->state builds only
 * against older releases. */
#ifndef BIRDCAGE_HAMLIB_COMPAT_H
#define BIRDCAGE_HAMLIB_COMPAT_H

#include <hamlib/rotator.h>
#if defined(__has_include)
#  if __has_include(<hamlib/port.h>)      /* 4.7+: HAMLIB_ROTPORT(); master needs it explicitly */
#    include <hamlib/port.h>
#  endif
#  if __has_include(<hamlib/rot_state.h>) /* 4.7+: struct rot_state + HAMLIB_ROTSTATE() */
#    include <hamlib/rot_state.h>
#  endif
#endif

#ifndef token_t /* 4.5.x: token_t is a typedef; 4.6+ #define it to hamlib_token_t */
typedef token_t hamlib_token_t;
#endif

/* 4.6+: through the exported rot_data_pointer(), as HAMLIB_ROTSTATE/HAMLIB_ROTPORT do, but with a
 * C++ cast (their C cast trips -Wold-style-cast in C++ code). */
#if defined(HAMLIB_ROTSTATE)
#  define WG_ROTSTATE(r) static_cast<struct rot_state *>(rot_data_pointer((r), RIG_PTRX_ROTSTATE))
#else
#  define WG_ROTSTATE(r) (&(r)->state)
#endif

#if defined(HAMLIB_ROTPORT)
#  define WG_ROTPORT(r) static_cast<hamlib_port_t *>(rot_data_pointer((r), RIG_PTRX_ROTPORT))
#else
#  define WG_ROTPORT(r) (&(r)->state.rotport)
#endif

#endif
