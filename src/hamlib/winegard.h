// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

/* C ABI of the Winegard rotator backend: what Hamlib's rot_reg.c would call if the backend were
 * compiled into Hamlib (DECLARE_INITROT_BACKEND(winegard) expands to this name for ABI 4). */
#ifndef BIRDCAGE_WINEGARD_H
#define BIRDCAGE_WINEGARD_H

#ifdef __cplusplus
extern "C" {
#endif

/* Registers one rot_caps per supported Winegard firmware variant. Returns RIG_OK, or the first
 * rot_register() error (e.g. -RIG_EINVAL when a model number is already taken). */
__attribute__((visibility("default"))) int initrots4_winegard(void *be_handle);

#ifdef __cplusplus
}
#endif

#endif
