/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* Copyright (C) 2026 the birdcage authors */

/* Hides the Hamlib API differences between 4.5.4 (Debian bookworm), 4.6, 4.7 and master, for C and
 * C++. Never touch rot->state directly: master moved the rotator state and port out of struct
 * s_rot, so a backend that dereferences rot->state builds only against older releases.
 * In a Hamlib tree (IN_HAMLIB, which its configure defines) the backend uses Hamlib's own
 * ROTSTATE()/ROTPORT(); the preload build reaches the state and port through the exported
 * rot_data_pointer() (4.6+), as the public HAMLIB_ROTSTATE/HAMLIB_ROTPORT do, or through
 * rot->state (4.5). */
#ifndef BIRDCAGE_HAMLIB_COMPAT_H
#define BIRDCAGE_HAMLIB_COMPAT_H

#include <hamlib/rotator.h>
#if defined(__has_include)
#if __has_include(<hamlib/port.h>) /* 4.7+: HAMLIB_ROTPORT(); master needs it explicitly */
#include <hamlib/port.h>
#endif
#if __has_include(<hamlib/rot_state.h>) /* 4.7+: struct rot_state + ROTSTATE()/HAMLIB_ROTSTATE() */
#include <hamlib/rot_state.h>
#endif
#endif

#ifndef token_t /* 4.5.x: token_t is a typedef; 4.6+ #define it to hamlib_token_t */
typedef token_t hamlib_token_t;
#endif

#if defined(IN_HAMLIB)
#define WG_ROTSTATE(r) ROTSTATE(r)
#define WG_ROTPORT(r) ROTPORT(r)
#elif defined(HAMLIB_ROTSTATE) && defined(__cplusplus)
/* A C++ cast: the public macros' C cast trips -Wold-style-cast. */
#define WG_ROTSTATE(r) static_cast<struct rot_state*>(rot_data_pointer((r), RIG_PTRX_ROTSTATE))
#define WG_ROTPORT(r) static_cast<hamlib_port_t*>(rot_data_pointer((r), RIG_PTRX_ROTPORT))
#elif defined(HAMLIB_ROTSTATE)
#define WG_ROTSTATE(r) HAMLIB_ROTSTATE(r)
#define WG_ROTPORT(r) HAMLIB_ROTPORT(r)
#else
#define WG_ROTSTATE(r) (&(r)->state)
#define WG_ROTPORT(r) (&(r)->state.rotport)
#endif

#endif
