/* SPDX-License-Identifier: LGPL-2.1-or-later */
/*
 *  Hamlib Rotator backend - Winegard motorised satellite dishes
 *  Copyright (C) 2026 the birdcage authors
 *
 *   This library is free software; you can redistribute it and/or
 *   modify it under the terms of the GNU Lesser General Public
 *   License as published by the Free Software Foundation; either
 *   version 2.1 of the License, or (at your option) any later version.
 *
 *   This library is distributed in the hope that it will be useful,
 *   but WITHOUT ANY WARRANTY; without even the implied warranty of
 *   MERCHANTABILITY or FITNESS FOR A PARTICULAR PURPOSE.  See the GNU
 *   Lesser General Public License for more details.
 *
 *   You should have received a copy of the GNU Lesser General Public
 *   License along with this library; if not, write to the Free Software
 *   Foundation, Inc., 51 Franklin Street, Fifth Floor, Boston, MA  02110-1301  USA
 *
 */

/*
 * The C interface of the Winegard rotator backend: the operations the caps
 * (winegard.c) point at and the conf tables they list. The operations are
 * C++ (winegard_ops.cpp, winegard_conf.cpp); every one of them catches what
 * the C++ below it throws and returns a -RIG_E* code.
 */
#ifndef WINEGARD_H
#define WINEGARD_H

#include "winegard_hamlib.h"

#ifdef __cplusplus
extern "C" {
#endif

int winegard_rot_init(ROT *rot);
int winegard_rot_cleanup(ROT *rot);
int winegard_rot_open(ROT *rot);
int winegard_rot_close(ROT *rot);

int winegard_set_position(ROT *rot, azimuth_t az, elevation_t el);
int winegard_get_position(ROT *rot, azimuth_t *az, elevation_t *el);
int winegard_stop(ROT *rot);
int winegard_park(ROT *rot);
int winegard_reset(ROT *rot, rot_reset_t reset);
int winegard_get_status(ROT *rot, rot_status_t *status);
const char *winegard_get_info(ROT *rot);

int winegard_set_conf(ROT *rot, hamlib_token_t token, const char *val);
#if defined(BIRDCAGE_PRELOAD)
int winegard_get_conf(ROT *rot, hamlib_token_t token, char *val);
#endif
int winegard_get_conf2(ROT *rot, hamlib_token_t token, char *val, int val_len);
int winegard_set_ext_level(ROT *rot, hamlib_token_t token, value_t val);
int winegard_get_ext_level(ROT *rot, hamlib_token_t token, value_t *val);

/*
 * rotctl's raw `w` command: refused. The console is a session the backend
 * holds (its menu, its echo, the hazard rule), and raw text would go around
 * all three.
 */
int winegard_send_cmd(ROT *rot, const char *cmd, char *reply, int reply_len);

/*
 * Conf parameters per model: the same keys, with the model's own defaults
 * (its elevation limits, its pointing mode), as `rotctl -L` lists them.
 * Filled by winegard_init_tables() from the variant table, which the
 * backend's initialisation calls before it registers the caps.
 */
extern struct confparams winegard_auto_cfg_params[];
extern struct confparams winegard_hal000_cfg_params[];
extern struct confparams winegard_hal205_cfg_params[];
extern struct confparams winegard_pro_cfg_params[];
extern struct confparams winegard_carryout2003_cfg_params[];
extern struct confparams winegard_g2_cfg_params[];
/* The receiver's levels (`v RSSI`, `V LNB 13`), the same for every model. */
extern struct confparams winegard_ext_levels[];

/*
 * Fills the tables above; RIG_OK, or -RIG_EINTERNAL if the variant table
 * lacks a model.
 */
int winegard_init_tables(void);

#ifdef __cplusplus
}
#endif

#endif /* WINEGARD_H */
