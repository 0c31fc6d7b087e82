/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* Copyright (C) 2026 the birdcage authors */

/* The C interface of the Winegard rotator backend: the operations the caps (winegard.c) point at
 * and the conf tables they list. The operations are C++ (winegard_ops.cpp, winegard_conf.cpp)
 * over the birdcage core; nothing here needs a C++ compiler to be included. */
#ifndef WINEGARD_H
#define WINEGARD_H

#include "hamlib_compat.h"

#ifdef __cplusplus
extern "C" {
#endif

int winegard_rot_init(ROT* rot);
int winegard_rot_cleanup(ROT* rot);
int winegard_rot_open(ROT* rot);
int winegard_rot_close(ROT* rot);

int winegard_set_position(ROT* rot, azimuth_t az, elevation_t el);
int winegard_get_position(ROT* rot, azimuth_t* az, elevation_t* el);
int winegard_stop(ROT* rot);
int winegard_park(ROT* rot);
int winegard_reset(ROT* rot, rot_reset_t reset);
int winegard_get_status(ROT* rot, rot_status_t* status);
const char* winegard_get_info(ROT* rot);

int winegard_set_conf(ROT* rot, hamlib_token_t token, const char* val);
int winegard_get_conf(ROT* rot, hamlib_token_t token, char* val);
int winegard_get_conf2(ROT* rot, hamlib_token_t token, char* val, int val_len);
int winegard_set_ext_level(ROT* rot, hamlib_token_t token, value_t val);
int winegard_get_ext_level(ROT* rot, hamlib_token_t token, value_t* val);

/* Conf parameters per model: the same keys, with the model's own defaults (its elevation limits,
 * its pointing mode), as `rotctl -L` lists them. Filled by winegard_init_tables() from the core's
 * variant table, which the backend's initialisation calls before it registers the caps. */
extern struct confparams winegard_auto_cfg_params[];
extern struct confparams winegard_hal000_cfg_params[];
extern struct confparams winegard_hal205_cfg_params[];
extern struct confparams winegard_pro_cfg_params[];
extern struct confparams winegard_carryout2003_cfg_params[];
extern struct confparams winegard_g2_cfg_params[];
/* The receiver's levels (`v RSSI`, `V LNB 13`), the same for every model. */
extern struct confparams winegard_ext_levels[];

/* Fills the tables above; RIG_OK, or -RIG_EINTERNAL if the core's variant table lacks a model. */
int winegard_init_tables(void);

#ifdef __cplusplus
}
#endif

#endif /* WINEGARD_H */
