// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Command handlers shared by the variant menu tables. Each prints its reply lines; the engine
// prints the prompt afterwards (or when the activity a handler started has finished).
#pragma once

#include "engine.hpp"

namespace birdcage::sim::handlers {

// motor submenus
void angle(Engine&, const Args&);  // `a`, `a <id> <deg>`, `a <id> ±<d>`
void go_to(Engine&, const Args&);  // `g <az> <el> [<sk>]`
void home(Engine&, const Args&);   // `h <id>` / `h *`
void step_positions(Engine&, const Args&);
void max_velocity(Engine&, const Args&);
void max_accel(Engine&, const Args&);
void el_min_max_home(Engine&, const Args&);
void list_motors(Engine&, const Args&);        // G2 `l`
void el_angle_to_steps(Engine&, const Args&);  // G2 `ela2s`
void el_steps_to_angle(Engine&, const Args&);  // G2 `els2a`
void setter(Engine&, const Args&);             // needs arguments (`Invalid params`), otherwise no effect
void silent(Engine&, const Args&);             // accepted, prints nothing (`e`, `r`, `lnbdc`)

// nvs
void nvs_dump(Engine&, const Args&);
void nvs_edit(Engine&, const Args&);
void nvs_save(Engine&, const Args&);
void nvs_next(Engine&, const Args&);

// os / search
void os_id(Engine&, const Args&);
void os_tasks(Engine&, const Args&);
void os_kill(Engine&, const Args&);
void ngsearch_stop(Engine&, const Args&);

// root
void reboot(Engine&, const Args&);
void stow(Engine&, const Args&);

// G2 diagnostics
void dvb_rssi(Engine&, const Args&);
void dvb_lnbdc(Engine&, const Args&);
void dvb_config(Engine&, const Args&);
void dvb_quick_lock(Engine&, const Args&);
void dvb_channel(Engine&, const Args&);  // G2 `dis`
void dvb_stream(Engine&, const Args&);   // `snr`, `agc`, `lnbv`, `nid`, `stats`, `ls`, PEAK `rssits`
void dvb_fixed_reply(Engine&, const Args&);
void a3981_reply(Engine&, const Args&);  // `sm`, `ss`, `cm`, `reset`
void latlon(Engine&, const Args&);
void peak_switch_test(Engine&, const Args&);  // `ts`
void peak_stb(Engine&, const Args&);
void step_engage(Engine&, const Args&);
void step_reply(Engine&, const Args&);   // STEP `p`, `pid`
void hazard_only(Engine&, const Args&);  // `def`, EEPROM `inv`: counted, otherwise no effect
void eeprom_read(Engine&, const Args&);
void adc_board_id(Engine&, const Args&);
void adc_board_rev(Engine&, const Args&);
void adc_rssi(Engine&, const Args&);
void adc_scan(Engine&, const Args&);
void a3981_diag(Engine&, const Args&);
void dipswitch(Engine&, const Args&);
void step_max_velocity(Engine&, const Args&);
void step_accel(Engine&, const Args&);

}  // namespace birdcage::sim::handlers
