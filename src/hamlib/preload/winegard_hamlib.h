/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* Copyright (C) 2026 the birdcage authors */

/* What the backend needs of Hamlib, in the preload build: the public headers of the installed
 * Hamlib (4.5.4 on Debian 12, 4.6 or 4.7), and the two accessors a Hamlib tree has. Never touch
 * rot->state directly: master moved the rotator state and port out of struct s_rot. The preload
 * build reaches them through the exported rot_data_pointer() (4.6+), as the public
 * HAMLIB_ROTSTATE/HAMLIB_ROTPORT do, or through rot->state (4.5). A Hamlib tree takes
 * src/hamlib/intree/winegard_hamlib.h instead (its own headers, no shim). */
#ifndef WINEGARD_HAMLIB_H
#define WINEGARD_HAMLIB_H

#include <hamlib/rotator.h>
#if defined(__has_include)
#if __has_include(<hamlib/port.h>) /* 4.7+: HAMLIB_ROTPORT(); master needs it explicitly */
#include <hamlib/port.h>
#endif
#if __has_include(<hamlib/rot_state.h>) /* 4.7+: struct rot_state + HAMLIB_ROTSTATE() */
#include <hamlib/rot_state.h>
#endif
#endif

#ifndef token_t /* 4.5.x: token_t is a typedef; 4.6+ #define it to hamlib_token_t */
typedef token_t hamlib_token_t;
#endif

#if defined(HAMLIB_ROTSTATE) && defined(__cplusplus)
/* A C++ cast: the public macros' C cast trips -Wold-style-cast. */
#define ROTSTATE(r) static_cast<struct rot_state*>(rot_data_pointer((r), RIG_PTRX_ROTSTATE))
#define ROTPORT(r) static_cast<hamlib_port_t*>(rot_data_pointer((r), RIG_PTRX_ROTPORT))
#elif defined(HAMLIB_ROTSTATE)
#define ROTSTATE(r) HAMLIB_ROTSTATE(r)
#define ROTPORT(r) HAMLIB_ROTPORT(r)
#else
#define ROTSTATE(r) (&(r)->state)
#define ROTPORT(r) (&(r)->state.rotport)
#endif

#endif
