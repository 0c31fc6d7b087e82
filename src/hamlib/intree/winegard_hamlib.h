/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* Copyright (C) 2026 the birdcage authors */

/*
 * What the backend needs of Hamlib inside Hamlib's tree: its own headers.
 * The preload build takes src/hamlib/preload/winegard_hamlib.h instead.
 */
#ifndef WINEGARD_HAMLIB_H
#define WINEGARD_HAMLIB_H

#include "hamlib/rotator.h"

#include "hamlib/port.h" /* master: split out of rig.h, after rotator.h */
#include "hamlib/rot_state.h"

#endif /* WINEGARD_HAMLIB_H */
