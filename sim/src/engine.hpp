// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Internal state of the console engine and the data that describes a firmware variant.
// Variants differ only through their VariantProfile row (variants.cpp) and menu tables.
#pragma once

#include <array>
#include <functional>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "birdcage_sim/emulator.hpp"
#include "birdcage_sim/motor.hpp"
#include "birdcage_sim/sky.hpp"
#include "nvs.hpp"

namespace birdcage::sim {

struct Engine;
using Args = std::vector<std::string_view>;  // args[0] is the command word
using Handler = void (*)(Engine&, const Args&);

struct Menu;
struct Command {
    std::string_view word;
    Handler run;  // nullptr when the command only enters `submenu`
    const Menu* submenu;
    std::string_view help;  // INVENTED descriptions (only the `Enter <cmd> - …` shape is known, §6.3)
    bool (*available)(const Options&) = nullptr;  // nullptr = always
    bool listed = true;                           // false: accepted but left out of `?` (Options::unlisted_commands)
};

struct Menu {
    std::string_view prompt_name;  // prompt is prompt_name + ">" (or ">" in bare style)
    std::span<const Command> commands;
    Handler fallback = nullptr;  // unknown words; nullptr = unknown-command reply
    bool shell_root = false;     // `q` here does not leave a submenu (see Engine::quit)
};

enum class PositionFormat {
    travler,  // `AZ = <f> EL = <f> SK = <f>` (§3.3, §4.3, §5.3)
    g2,       // `Angle[0] = <f>` / `Angle[1] = <f>` (§6.3)
    none,     // 2003 Carryout: no position query at rest (§8.3)
};

enum class SearchStop {
    ngsearch_stop,        // HAL 2.05: `ngsearch` → `s` → `q` (§4.3)
    os_kill,              // HAL 0.0.00, Pro: `os` → `kill Search` (§3.3, §5.3)
    nvs_disable_tracker,  // G2: NVS 20 TRUE + `s` + reboot (§6.2, Appendix A)
    runs_out,             // 2003 Carryout: cannot be stopped, ends by itself (§8.2)
};

struct BootStep {
    // ready: the completion line is out; from here input is kept for the shell (late lines follow).
    // raw: bytes with no line ending (the captured G2's binary bursts).
    enum class Kind { line, raw, move, home, pause, ready };
    Kind kind;
    std::string text;      // line, raw
    std::size_t axis = 0;  // move, home
    double target = 0.0;   // move (mechanical degrees)
    double seconds = 0.0;  // pause
    bool burst = false;    // line: the next step follows at once (no boot_line_gap)
};

struct VariantProfile {
    Variant variant;
    const char* name;
    int baud;          // informational: a pty has no baud rate
    const Menu* root;  // console root after boot (Pro: the IDU console)
    PositionFormat position_format;
    bool move_ack_angle;      // G2: `Angle = <deg>` after `a <id> <deg>` (§6.3, §7.1)
    bool relative_moves;      // G2: `a <id> +d` / `-d` (§6.3)
    bool needs_homing;        // G2: axes read INT_MAX until homed; `h <id>` (§6.4)
    bool live_goto_output;    // 2003 Carryout: centidegree lines while `g` runs (§8.4)
    bool root_q_kills_shell;  // G2 (§6.5), subject to Options::g2_root_q_kills_shell
    bool fixed_prompts;       // G2 prompts are known (§6.3); others follow Options::prompt_style
    SearchStop search_stop;
    bool boot_prints_prompt;  // G2 prints TRK> when the tracker stays off (§6.2 item 5)
    AxisParams az, el, skew;  // mechanical travel + motion parameters
    double el_min, el_max;    // firmware limits unless NVS overrides them
    double el_stall_above;    // Pro: motor stalls above ~75 deg (§5.4); +inf elsewhere
    double stow_el;
    double home_az, home_el;  // where homing leaves the axes (G2: 0 and NVS 103 = 65)
    int nvs_min_el_index, nvs_max_el_index, nvs_disable_tracker_index;  // -1 = none
    std::size_t nvs_page_rows;  // `d` pages through the table (Pro, §5.3); 0 = all at once
    std::vector<NvsEntry> (*nvs_table)();
    std::vector<BootStep> (*boot_script)(const Engine&);
    bool g_aborts_on_input;  // default of Options::g_aborts_on_input
};

const VariantProfile& profile_for(Variant variant);

// One `?` entry: the command word and its description (dialect.cpp renders the listing).
struct HelpEntry {
    std::string word;
    std::string description;
};
// The lines of a generated `?` listing (HelpLayout::generated) for the menu whose prompt name is
// `menu_name`; `q` and `?` are added as the grammar says.
std::vector<std::string> render_help(const HelpGrammar& grammar, std::string_view menu_name,
                                     std::vector<HelpEntry> entries);

struct Busy {
    // stream: `finish` prints one line every `period` seconds until any byte arrives; then the
    // stream ends at the prompt, or (drop_to_root) with `Terminating shell.` at the root.
    enum class Kind { none, until_idle, until_time, goto_move, stream };
    Kind kind = Kind::none;
    double until = 0.0;
    double next_live_line = 0.0;
    std::function<void(Engine&)> finish;  // prints the rest of the reply and the prompt
    double period = 0.0;                  // stream
    bool drop_to_root = false;            // stream
    bool endless = false;                 // stream: input does not end it (only a power cycle does)
};

struct Engine {
    Engine(const Options& options);

    // --- I/O ----------------------------------------------------------------------------
    void feed(std::string_view bytes);
    void advance(double dt);
    void print(std::string_view text);       // raw bytes to the client
    void print_line(std::string_view text);  // text + line ending
    void print_prompt();
    std::string eol() const;
    std::string take_output();  // bytes on the line (all, or paced at the baud rate)
    bool g_aborts_on_input() const { return options.g_aborts_on_input.value_or(profile.g_aborts_on_input); }

    // --- shared behaviour used by handlers ----------------------------------------------
    void unknown_command();
    // A known command with missing or bad arguments: the captured G2's `Invalid params`; elsewhere
    // the unknown-command reply (no other console's text is known).
    void invalid_params();
    bool captured_g2() const {
        return profile.variant == Variant::carryout_g2 && options.g2_console == G2Console::captured;
    }
    std::size_t reply_indent() const;  // Options::position_indent, or the console's
    HelpLayout help_layout() const;    // Options::help_layout, or the console's
    // One hazard per command line at most: the dispatch counts by the core's hazard rule (execute())
    // and a handler may count the same line again for what only it can see (an unhomed axis, the
    // Pro's elevation stall).
    void count_hazard() {
        if (hazard_counted_for_line_)
            return;
        ++hazards;
        if (hazard_lines.size() < 1000)
            hazard_lines.push_back(executing_line_);
        hazard_counted_for_line_ = true;
    }
    void kill_shell(std::string_view last_words);  // console dead until power cycle
    void reboot();
    void start_boot();
    void start_search();
    void stop_search();
    void wait_until_idle(std::function<void(Engine&)> finish);
    void wait_for(double seconds, std::function<void(Engine&)> finish);
    void start_goto(std::function<void(Engine&)> finish);
    // A streaming command (`line` every `period` seconds until input, see Busy::Kind::stream).
    void start_stream(double period, bool drop_to_root, std::function<void(Engine&)> line, bool endless = false);
    // Fault injection: the move of `axis` (AZ or EL) in progress, or its next one, stalls
    // halfway: the axis stops dead, queued moves are dropped, `AZ/EL MOTOR STALLED` (§6.3).
    void inject_motor_stall(std::size_t axis);
    double displayed_az() const;
    double reported_az() const;  // per Options::az_report
    // Where the beam points on the sky (docs/sky.md §1: Options::mount applied to the axes), and
    // one 20 ms RSSI read there at the sky clock's UTC.
    AzEl beam_direction() const;
    int read_rssi();
    double el_limit_min() const { return el_min_active_; }
    double el_limit_max() const { return el_max_active_; }
    bool booting() const { return booting_; }

    const Options options;
    const VariantProfile& profile;
    double now = 0.0;
    MotorModel motors;
    SkyModel sky;
    double epoch;  // UTC of simulated time 0 (Options::epoch or the wall clock at construction)
    std::mt19937 rng;
    std::vector<const Menu*> menus;  // menus.front() is the console root
    std::string output;              // printed, not yet on the line
    std::vector<std::string> commands;
    std::vector<Sample> history;
    unsigned hazards = 0;
    std::vector<std::string> hazard_lines;  // the command line of each hazard counted
    bool shell_alive = true;
    bool search = false;
    double search_ends_at = 0.0;
    double search_resume_at = 0.0;
    std::array<bool, 2> homed{true, true};
    Busy busy;
    NvsTable nvs;
    int nvs_cursor = -1;
    // The LNB supply the sky model hears: 18 V at boot (`Enabled LNB ODU 18V`, §6.2 item 4).
    LnbSupply lnb_supply = LnbSupply::stb_18v;
    unsigned motor_stalls = 0;    // injected stalls that have happened
    std::vector<TruthRow> truth;  // with Options::truth_path: rows not yet taken (Console::take_truth)

private:
    void record_received(char byte);
    void process_pending();
    void execute(const std::string& line);
    void quit();
    void help();
    void tick();  // one small simulated step's events
    void run_boot();
    void start_boot_moves();
    void run_search();
    void run_busy();
    void record_sample();
    void record_truth();
    void finish_boot();
    void apply_nvs_limits();
    void finish_busy();
    void end_stream();
    void run_stalls();
    void run_idle_line();
    void run_line(double dt);

    struct StallArm {
        bool armed = false;
        bool tracking = false;  // the armed axis is moving; stall_at is set
        double stall_at = 0.0;  // mechanical position where it stalls
        double direction = 0.0;
        double target = 0.0;  // the move being tracked
    };
    std::array<StallArm, 2> stall_arms_{};

    bool hazard_counted_for_line_ = false;
    std::string executing_line_;
    std::string line_;
    std::string pending_;
    std::string received_line_;
    char previous_raw_ = 0;
    bool booting_ = false;
    bool boot_input_kept_ = false;    // past the completion line: input waits for the shell
    double input_deaf_until_ = -1.0;  // Options::boot_input_drop window
    double next_idle_line_ = 0.0;
    std::string on_line_;       // pace_at_line_rate: bytes already sent
    double line_credit_ = 0.0;  // bytes the line may still send this tick
    std::vector<BootStep> boot_steps_;
    std::size_t boot_index_ = 0;
    double boot_resume_at_ = 0.0;
    // Options::boot_moves_overlap: the boot's moves run as a task of their own, until the motors
    // rest (what a console command queued behind them runs too).
    bool boot_motion_ = false;
    bool truth_moving_ = false;
    double next_truth_at_ = 0.0;  // the next row on the 0.1 s grid
    double el_min_active_ = 0.0;
    double el_max_active_ = 90.0;
};

}  // namespace birdcage::sim
