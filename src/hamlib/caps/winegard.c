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
 * One rot_caps per firmware variant of the Winegard consoles (Trav'ler,
 * Trav'ler Pro, Carryout, Carryout G2), plus one that identifies the variant
 * at open. The operations are C++ behind the C interface in winegard.h, as
 * rotators/indi does it; this file is the backend as Hamlib lists it.
 *
 * .priv names the model's row in the backend's variant table; rot_init
 * refuses caps whose name, rate or reset disagree with that row.
 *
 * The az/el ranges are what Hamlib's own range check lets through (it
 * answers RPRT -1 outside them, and Gpredict disengages after five errors):
 * they cover Gpredict's 0..360 and -180..180 azimuth modes and its default
 * 0..90 elevation. The backend clamps each target to what the variant can
 * really do (conf parameters el_min, el_max, az_min, az_max).
 *
 * .timeout bounds each read of the console through Hamlib's port I/O; a
 * longer wait of the backend (a slew, a boot) is several such reads.
 * .retry is how many failed exchanges in a row the backend retries before
 * it re-synchronises the console.
 */

#include <stddef.h>

#include "hamlib/rotator.h"
#include "register.h"

#include "winegard.h"

#define WINEGARD_VERSION "20261207.0"

#define WINEGARD_MIN_AZ (-180.0)
#define WINEGARD_MAX_AZ 540.0
#define WINEGARD_MIN_EL 0.0
#define WINEGARD_MAX_EL 90.0

/*
 * Identifies the variant at open (57600 baud unless -s says otherwise; a G2
 * needs 115200). It keeps the reset: which variant it is, and whether it
 * can home, is known only at open.
 */
static const struct rot_caps winegard_auto_caps = {
    ROT_MODEL(ROT_MODEL_WINEGARD_AUTO),
    .model_name = "Auto-detect",
    .mfg_name = "Winegard",
    .version = WINEGARD_VERSION,
    .copyright = "LGPL",
    .status = RIG_STATUS_ALPHA,
    .rot_type = ROT_TYPE_AZEL,
    .port_type = RIG_PORT_SERIAL,
    .serial_rate_min = 9600,
    .serial_rate_max = 57600,
    .serial_data_bits = 8,
    .serial_stop_bits = 1,
    .serial_parity = RIG_PARITY_NONE,
    .serial_handshake = RIG_HANDSHAKE_NONE,
    .write_delay = 0,
    .post_write_delay = 0,
    .timeout = 1000,
    .retry = 1,
    .has_status = ROT_STATUS_MOVING | ROT_STATUS_BUSY,
    .min_az = WINEGARD_MIN_AZ,
    .max_az = WINEGARD_MAX_AZ,
    .min_el = WINEGARD_MIN_EL,
    .max_el = WINEGARD_MAX_EL,
    .priv = "auto",
    .cfgparams = winegard_auto_cfg_params,
    .extlevels = winegard_ext_levels,
    .rot_init = winegard_rot_init,
    .rot_cleanup = winegard_rot_cleanup,
    .rot_open = winegard_rot_open,
    .rot_close = winegard_rot_close,
    .set_conf = winegard_set_conf,
#if defined(BIRDCAGE_PRELOAD)
    .get_conf = winegard_get_conf,
#endif
    .get_conf2 = winegard_get_conf2,
    .set_position = winegard_set_position,
    .get_position = winegard_get_position,
    .stop = winegard_stop,
    .park = winegard_park,
    .reset = winegard_reset,
    .get_info = winegard_get_info,
    .get_status = winegard_get_status,
    .set_ext_level = winegard_set_ext_level,
    .get_ext_level = winegard_get_ext_level,
#if !defined(BIRDCAGE_PRELOAD)
    .send_cmd = winegard_send_cmd,
#endif
};

/*
 * Trav'ler, HAL 0.0.00 (e.g. LG-2112): RS-485 on the IDU's RJ-25 "Factory
 * Only" port.
 */
static const struct rot_caps winegard_hal000_caps = {
    ROT_MODEL(ROT_MODEL_WINEGARD_HAL000),
    .model_name = "Trav'ler HAL 0.0.00",
    .mfg_name = "Winegard",
    .version = WINEGARD_VERSION,
    .copyright = "LGPL",
    .status = RIG_STATUS_ALPHA,
    .rot_type = ROT_TYPE_AZEL,
    .port_type = RIG_PORT_SERIAL,
    .serial_rate_min = 9600,
    .serial_rate_max = 57600,
    .serial_data_bits = 8,
    .serial_stop_bits = 1,
    .serial_parity = RIG_PARITY_NONE,
    .serial_handshake = RIG_HANDSHAKE_NONE,
    .write_delay = 0,
    .post_write_delay = 0,
    .timeout = 1000,
    .retry = 1,
    .has_status = ROT_STATUS_MOVING | ROT_STATUS_BUSY,
    .min_az = WINEGARD_MIN_AZ,
    .max_az = WINEGARD_MAX_AZ,
    .min_el = WINEGARD_MIN_EL,
    .max_el = WINEGARD_MAX_EL,
    .priv = "hal000",
    .cfgparams = winegard_hal000_cfg_params,
    .extlevels = winegard_ext_levels,
    .rot_init = winegard_rot_init,
    .rot_cleanup = winegard_rot_cleanup,
    .rot_open = winegard_rot_open,
    .rot_close = winegard_rot_close,
    .set_conf = winegard_set_conf,
#if defined(BIRDCAGE_PRELOAD)
    .get_conf = winegard_get_conf,
#endif
    .get_conf2 = winegard_get_conf2,
    .set_position = winegard_set_position,
    .get_position = winegard_get_position,
    .stop = winegard_stop,
    .park = winegard_park,
    .get_info = winegard_get_info,
    .get_status = winegard_get_status,
    .set_ext_level = winegard_set_ext_level,
    .get_ext_level = winegard_get_ext_level,
#if !defined(BIRDCAGE_PRELOAD)
    .send_cmd = winegard_send_cmd,
#endif
};

/*
 * Trav'ler, HAL 2.05.003.
 */
static const struct rot_caps winegard_hal205_caps = {
    ROT_MODEL(ROT_MODEL_WINEGARD_HAL205),
    .model_name = "Trav'ler HAL 2.05",
    .mfg_name = "Winegard",
    .version = WINEGARD_VERSION,
    .copyright = "LGPL",
    .status = RIG_STATUS_ALPHA,
    .rot_type = ROT_TYPE_AZEL,
    .port_type = RIG_PORT_SERIAL,
    .serial_rate_min = 9600,
    .serial_rate_max = 57600,
    .serial_data_bits = 8,
    .serial_stop_bits = 1,
    .serial_parity = RIG_PARITY_NONE,
    .serial_handshake = RIG_HANDSHAKE_NONE,
    .write_delay = 0,
    .post_write_delay = 0,
    .timeout = 1000,
    .retry = 1,
    .has_status = ROT_STATUS_MOVING | ROT_STATUS_BUSY,
    .min_az = WINEGARD_MIN_AZ,
    .max_az = WINEGARD_MAX_AZ,
    .min_el = WINEGARD_MIN_EL,
    .max_el = WINEGARD_MAX_EL,
    .priv = "hal205",
    .cfgparams = winegard_hal205_cfg_params,
    .extlevels = winegard_ext_levels,
    .rot_init = winegard_rot_init,
    .rot_cleanup = winegard_rot_cleanup,
    .rot_open = winegard_rot_open,
    .rot_close = winegard_rot_close,
    .set_conf = winegard_set_conf,
#if defined(BIRDCAGE_PRELOAD)
    .get_conf = winegard_get_conf,
#endif
    .get_conf2 = winegard_get_conf2,
    .set_position = winegard_set_position,
    .get_position = winegard_get_position,
    .stop = winegard_stop,
    .park = winegard_park,
    .get_info = winegard_get_info,
    .get_status = winegard_get_status,
    .set_ext_level = winegard_set_ext_level,
    .get_ext_level = winegard_get_ext_level,
#if !defined(BIRDCAGE_PRELOAD)
    .send_cmd = winegard_send_cmd,
#endif
};

/*
 * Trav'ler Pro (e.g. SK2DISH): USB CDC-ACM on the IDU's rear port; the rate
 * is irrelevant.
 */
static const struct rot_caps winegard_pro_caps = {
    ROT_MODEL(ROT_MODEL_WINEGARD_PRO),
    .model_name = "Trav'ler Pro",
    .mfg_name = "Winegard",
    .version = WINEGARD_VERSION,
    .copyright = "LGPL",
    .status = RIG_STATUS_ALPHA,
    .rot_type = ROT_TYPE_AZEL,
    .port_type = RIG_PORT_SERIAL,
    .serial_rate_min = 9600,
    .serial_rate_max = 57600,
    .serial_data_bits = 8,
    .serial_stop_bits = 1,
    .serial_parity = RIG_PARITY_NONE,
    .serial_handshake = RIG_HANDSHAKE_NONE,
    .write_delay = 0,
    .post_write_delay = 0,
    .timeout = 1000,
    .retry = 1,
    .has_status = ROT_STATUS_MOVING | ROT_STATUS_BUSY,
    .min_az = WINEGARD_MIN_AZ,
    .max_az = WINEGARD_MAX_AZ,
    .min_el = WINEGARD_MIN_EL,
    .max_el = WINEGARD_MAX_EL,
    .priv = "pro",
    .cfgparams = winegard_pro_cfg_params,
    .extlevels = winegard_ext_levels,
    .rot_init = winegard_rot_init,
    .rot_cleanup = winegard_rot_cleanup,
    .rot_open = winegard_rot_open,
    .rot_close = winegard_rot_close,
    .set_conf = winegard_set_conf,
#if defined(BIRDCAGE_PRELOAD)
    .get_conf = winegard_get_conf,
#endif
    .get_conf2 = winegard_get_conf2,
    .set_position = winegard_set_position,
    .get_position = winegard_get_position,
    .stop = winegard_stop,
    .park = winegard_park,
    .get_info = winegard_get_info,
    .get_status = winegard_get_status,
    .set_ext_level = winegard_set_ext_level,
    .get_ext_level = winegard_get_ext_level,
#if !defined(BIRDCAGE_PRELOAD)
    .send_cmd = winegard_send_cmd,
#endif
};

/*
 * Carryout (2003), HAL 1.00.065: reports its position only while it moves.
 */
static const struct rot_caps winegard_carryout2003_caps = {
    ROT_MODEL(ROT_MODEL_WINEGARD_CARRYOUT2003),
    .model_name = "Carryout HAL 1.00.065",
    .mfg_name = "Winegard",
    .version = WINEGARD_VERSION,
    .copyright = "LGPL",
    .status = RIG_STATUS_ALPHA,
    .rot_type = ROT_TYPE_AZEL,
    .port_type = RIG_PORT_SERIAL,
    .serial_rate_min = 9600,
    .serial_rate_max = 57600,
    .serial_data_bits = 8,
    .serial_stop_bits = 1,
    .serial_parity = RIG_PARITY_NONE,
    .serial_handshake = RIG_HANDSHAKE_NONE,
    .write_delay = 0,
    .post_write_delay = 0,
    .timeout = 1000,
    .retry = 1,
    .has_status = ROT_STATUS_MOVING | ROT_STATUS_BUSY,
    .min_az = WINEGARD_MIN_AZ,
    .max_az = WINEGARD_MAX_AZ,
    .min_el = WINEGARD_MIN_EL,
    .max_el = WINEGARD_MAX_EL,
    .priv = "carryout2003",
    .cfgparams = winegard_carryout2003_cfg_params,
    .extlevels = winegard_ext_levels,
    .rot_init = winegard_rot_init,
    .rot_cleanup = winegard_rot_cleanup,
    .rot_open = winegard_rot_open,
    .rot_close = winegard_rot_close,
    .set_conf = winegard_set_conf,
#if defined(BIRDCAGE_PRELOAD)
    .get_conf = winegard_get_conf,
#endif
    .get_conf2 = winegard_get_conf2,
    .set_position = winegard_set_position,
    .get_position = winegard_get_position,
    .stop = winegard_stop,
    .park = winegard_park,
    .get_info = winegard_get_info,
    .get_status = winegard_get_status,
    .set_ext_level = winegard_set_ext_level,
    .get_ext_level = winegard_get_ext_level,
#if !defined(BIRDCAGE_PRELOAD)
    .send_cmd = winegard_send_cmd,
#endif
};

/*
 * Carryout G2 (firmware 02.02.48), G2+ and the other 115200-baud Carryouts:
 * RS-422. The only variant that homes (`R 1`).
 */
static const struct rot_caps winegard_g2_caps = {
    ROT_MODEL(ROT_MODEL_WINEGARD_G2),
    .model_name = "Carryout G2",
    .mfg_name = "Winegard",
    .version = WINEGARD_VERSION,
    .copyright = "LGPL",
    .status = RIG_STATUS_ALPHA,
    .rot_type = ROT_TYPE_AZEL,
    .port_type = RIG_PORT_SERIAL,
    .serial_rate_min = 9600,
    .serial_rate_max = 115200,
    .serial_data_bits = 8,
    .serial_stop_bits = 1,
    .serial_parity = RIG_PARITY_NONE,
    .serial_handshake = RIG_HANDSHAKE_NONE,
    .write_delay = 0,
    .post_write_delay = 0,
    .timeout = 1000,
    .retry = 1,
    .has_status = ROT_STATUS_MOVING | ROT_STATUS_BUSY,
    .min_az = WINEGARD_MIN_AZ,
    .max_az = WINEGARD_MAX_AZ,
    .min_el = WINEGARD_MIN_EL,
    .max_el = WINEGARD_MAX_EL,
    .priv = "g2",
    .cfgparams = winegard_g2_cfg_params,
    .extlevels = winegard_ext_levels,
    .rot_init = winegard_rot_init,
    .rot_cleanup = winegard_rot_cleanup,
    .rot_open = winegard_rot_open,
    .rot_close = winegard_rot_close,
    .set_conf = winegard_set_conf,
#if defined(BIRDCAGE_PRELOAD)
    .get_conf = winegard_get_conf,
#endif
    .get_conf2 = winegard_get_conf2,
    .set_position = winegard_set_position,
    .get_position = winegard_get_position,
    .stop = winegard_stop,
    .park = winegard_park,
    .reset = winegard_reset,
    .get_info = winegard_get_info,
    .get_status = winegard_get_status,
    .set_ext_level = winegard_set_ext_level,
    .get_ext_level = winegard_get_ext_level,
#if !defined(BIRDCAGE_PRELOAD)
    .send_cmd = winegard_send_cmd,
#endif
};

static const struct rot_caps *const winegard_caps_list[] = {
    &winegard_auto_caps, &winegard_hal000_caps,       &winegard_hal205_caps,
    &winegard_pro_caps,  &winegard_carryout2003_caps, &winegard_g2_caps,
};

DECLARE_INITROT_BACKEND(winegard)
{
    int first_error = RIG_OK;
    size_t i;

    rot_debug(RIG_DEBUG_VERBOSE, "%s called\n", __func__);

    if (winegard_init_tables() != RIG_OK)
    {
        return -RIG_EINTERNAL;
    }

    for (i = 0; i < sizeof(winegard_caps_list) / sizeof(winegard_caps_list[0]);
         i++)
    {
        int retval = rot_register(winegard_caps_list[i]);

        if (retval != RIG_OK && first_error == RIG_OK)
        {
            first_error = retval;
        }
    }

    return first_error;
}
