// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage dish emulator: a pty that behaves like the serial console of a Winegard motorized
// dish. Written from docs/firmware.md (section numbers cited as §n), independently
// of the backend in src/, so that it can act as the test oracle.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "birdcage_sim/sky_geometry.hpp"

namespace birdcage::sim {

enum class Variant { travler_hal000, travler_hal205, travler_pro, carryout2003, carryout_g2 };

// "hal000", "hal205", "pro", "carryout2003", "g2"
std::optional<Variant> parse_variant(std::string_view name);
const char* variant_name(Variant);

// Switches for behaviour docs/firmware.md (§14, Appendix C) leave open. Defaults are the most
// plausible reading of the notes; text marked INVENTED is not known firmware output.
// Output line ending. §14 HAL0.6, G2.10: unknown; CR LF from birdcage's bare-CR probe ("CR LF then
// TRK>", §6.1). LF CR is a common embedded-shell habit; CR alone breaks travler_init.py's
// readline (§3.6) and is offered only to try that.
enum class LineEnding { crlf, lf, lfcr, cr };
enum class AzReport { displayed, mechanical };   // §14 G2.4 (and §3.3: `a` may show the wrap)
enum class OutOfRange { clamp, reject };         // §14 HAL0.4, G2.6; §3.4 "unreliable below 15"
enum class MoveAck { immediate, after_motion };  // §14 G2.3
// Trav'ler/Carryout 2003 prompts (§14 HAL0.1, CO.2): `TRK>`/`MOT>`, `>` everywhere, or `>` at the
// root while submenus name themselves (`MOT>`).
enum class PromptStyle { named, bare, bare_root };
enum class BootMarker { no_gps, no_lnb_voltage };  // HAL 2.05 boot-complete line, §4.2
// What a Trav'ler (HAL 0.0.00, 2.05, Pro) does with its motors at power-up, before its ready line
// (§3.2, §5.2, §14 HAL0.9). The sources say only that it calibrates, "finding its position and wrap
// limits", and of the Pro that it "may initialize and home (does not happen on all dishes)":
//  park         AZ to 0, then EL to 45, and it stays there (the emulator's reading before this
//               switch; the end point is INVENTED);
//  home_return  AZ to its stop at 0 and back to where it was (a wrap-limit search that ends where it
//               began; INVENTED that it returns);
//  none         no move (the dish that does not home).
enum class TravlerBootMoves { park, home_return, none };
std::optional<TravlerBootMoves> parse_travler_boot_moves(std::string_view name);  // "park", "home-return", "none"
const char* travler_boot_moves_name(TravlerBootMoves);
// How an absolute azimuth target maps onto the mechanical travel (§14 G2.4; §2, §3.4, §3.5):
//  nearest       0..360 to the wrap branch nearest the axis; an in-travel value beyond 0..360 as is;
//  literal       the number is a mechanical angle; outside the travel: the out-of-range behaviour.
//                Where the travel is mostly negative (G2, §6.4) and a leading '-' makes a relative
//                move (§6.3), a number outside the travel names number - 360: one fixed branch per
//                value (0..23.33 itself, 23.33..360 -> -336.67..0), the only way a console that has
//                no negative absolute numbers can take numbers literally;
//  wrap_manager  the firmware keeps the axis inside the 360-degree sector that does not pass
//                through az_wrap_point: every target (any number, relative moves too) is taken
//                modulo 360 into that sector, so a target across the wrap point is reached the long
//                way round (§2 "reverses to reach the target from the other side", §3.5 "with wrap
//                position at 0 the dish stops and reverses mid-track", §6.3 `w`/`sw`).
enum class AzMapping { nearest, literal, wrap_manager };
std::optional<AzMapping> parse_az_mapping(std::string_view name);  // "nearest", "literal", "wrap_manager"
// `?` listing layout. Only the G2's is captured (`available`, sim/transcripts/captured/); the
// reconstructed G2 console printed `Enter <cmd> - Description` per line plus the usage line
// `help [<command>]` (the predecessor's summary, §6.3). No source shows a Trav'ler or 2003 Carryout listing
// verbatim (§3.3, §8.3 say only that `?` lists the commands), so the others are the shapes a
// firmware console plausibly prints, each filled from the same menu table.
enum class HelpLayout {
    available,      // the captured G2's: `Available commands:`, then `   <word padded to 14><description>`
    described,      // `Enter <a> - Angle ...` per command, `Enter <q> - ...`, `help [<command>]`
    words,          // bare command words, one per line
    one_line,       // all words on one line, space-separated
    comma_line,     // all words on one line, `, `-separated
    colon_table,    // `a            : Angle ...` (word padded to the longest)
    tab_table,      // `a<TAB>Angle ...`
    labelled_line,  // `Commands: a g q ?`: a label, then all words on one line (INVENTED label)
    generated,      // drawn by the dialect generator: Options::help_grammar (sim/README.md, "Dialects")
};

// The shape of a `?` listing, from the dialect generator's grammar (sim/README.md, "Dialects").
// Every listing is: title lines, the entries, footer lines. Entries are the menu's command words
// (plus `q` and `?` if asked), each `<number><prefix><open>word<close>` and, in rows, a separator
// and the description.
enum class HelpArrangement {
    rows,     // one entry per line, with or without its description
    packed,   // label, then every word on one line (wrapped at wrap_width)
    columns,  // words only, `columns` per line, padded to column_width
};
enum class TextCase { as_is, upper, lower };
struct HelpGrammar {
    std::vector<std::string> title_lines;   // printed before the entries ("" = an empty line)
    std::vector<std::string> footer_lines;  // printed after them
    HelpArrangement arrangement = HelpArrangement::rows;
    std::string label;                  // packed: before the first word (e.g. "Commands: ")
    std::string word_open, word_close;  // brackets around each word
    std::string row_prefix;             // rows: before each entry (e.g. "  ", "- ")
    std::string numbering;              // rows: "" or a pattern with '#' for the number ("#. ", "[#] ")
    TextCase word_case = TextCase::as_is;
    bool descriptions = true;       // rows: the command's description after the word
    std::string separator = " - ";  // rows: between word and description
    bool pad_words = false;         // rows: descriptions aligned in one column
    TextCase description_case = TextCase::as_is;
    std::string packed_separator = " ";        // packed: between words
    std::size_t columns = 4;                   // columns: words per line
    std::size_t column_width = 12;             // columns: each cell padded to this width
    std::size_t wrap_width = 0;                // 0: no wrapping; else longer lines continue on the next
    std::size_t continuation_indent = 0;       // spaces before a continuation line
    bool list_quit = true, list_help = false;  // `q` and `?` among the entries
    bool sorted = false;                       // words in alphabetical order instead of table order
};

// A line (or only a silence) the dialect generator adds to the boot log. Boot logs are the
// variant's documented lines (docs/firmware.md §6.2, §3.2, §4.2) with extras inserted.
struct ExtraBootLine {
    // Inserted before the documented line with this index (0 = before the first; the number of
    // documented lines = after the last, i.e. after the completion marker, where input is kept).
    std::size_t before_documented = 0;
    std::string text;             // empty: only the silence
    double silence_before = 0.0;  // simulated seconds of quiet before the line
};
// What `h` prints when the AZ axis has homed (§14 G2.8). The G2 02.02.48's wrap line is known
// from its homing output (§6.3); mjlangan's G2+ client waits for `AZ - Angle: 1 Wrap: 0` (§7.1,
// shape inferred from its regex).
enum class HomeReport { wrap_limits, g2plus_status };
// Trav'ler `a` reply (§14 HAL0.3): birdcage documents one line `AZ = .. EL = .. SK = ..` (§3.3);
// the upstream client's patterns would also find the fields on separate lines.
enum class TravlerPositionLayout { one_line, line_per_axis };
// Transcript replay (docs/transcripts.md): strict stops at the first unexpected command and reports
// it through Emulator::replay_failure(); lenient hands the session over to the model console.
enum class ReplayMode { off, strict, lenient };

// Faults of the serial line between the dish and the client (docs/reliability.md, docs/firmware.md §6.1). They
// are wire properties and run in real time, not scaled by Options::time_scale. Settable at
// construction and live through the Emulator setters.
struct LineFaults {
    double idle_noise_bps = 0.0;     // random bytes per real second while the line is idle
    bool inverted_polarity = false;  // every byte the dish sends is bit-inverted (swapped RX pair)
    bool ignore_input = false;       // the dish never sees client bytes (swapped TX pair)
    double drop_probability = 0.0;   // each byte the dish sends is lost with this probability
    int pace_baud = 0;               // 0: as fast as the pty takes it; else 10 bits per byte
};

// Bookkeeping of what the injected faults did.
struct FaultCounters {
    std::uint64_t garbage_bytes = 0;    // noise written to the line (inject_garbage + idle noise)
    std::uint64_t dropped_bytes = 0;    // dish bytes lost to set_drop_probability
    std::uint64_t ignored_bytes = 0;    // client bytes lost to set_ignore_input or a hang-up
    std::uint64_t discarded_bytes = 0;  // dish bytes printed while the adapter was unplugged
    unsigned motor_stalls = 0;          // injected motor stalls that have happened
    std::uint64_t paced_bytes = 0;      // bytes written at set_output_pacing's rate
};

// Overrides of the variant's motor parameters (unset: the variant's value). Simulated time.
struct MotorDynamics {
    double startup_delay = 0.0;         // seconds from a move command to the first motion
    std::optional<double> az_velocity;  // deg/s
    std::optional<double> el_velocity;  // deg/s
    std::optional<double> accel;        // deg/s^2, both axes
};

// Which G2 console the emulator plays (docs/firmware.md §6, sim/README.md "The G2 console"):
//  captured       the console of the real 02.02.48 session captures (sim/transcripts/captured/):
//                 its boot, texts, indentation, listings, errors and menus, byte for byte where
//                 they show them;
//  reconstructed  the console this emulator played before any capture existed, rebuilt from the
//                 predecessor's summaries (paraphrased boot with homing, `Enter <cmd> - ...` help,
//                 `Unknown command`, `g` in MOT>, `reboot`/`stow` at the root, no indentation).
enum class G2Console { captured, reconstructed };
std::optional<G2Console> parse_g2_console(std::string_view name);  // "captured", "reconstructed"

// What `q` at the G2's `TRK>` does (docs/firmware.md §6.5: disputed).
enum class G2RootQ {
    kill,      // `Terminating shell.`, then the console is dead until a power cycle (the predecessor)
    harmless,  // `TRK>` reprinted, as the clients that send `q` first need (§6.6, §7)
    restart,   // `Terminating shell.`, then a fresh `TRK>`: what interrupting DVB `ls` shows (§6.5)
};

struct Options {
    Variant variant = Variant::carryout_g2;
    double time_scale = 1.0;                   // simulated seconds per real second
    bool already_booted = true;                // false: boot log first (scaled time), then post-boot behaviour
    bool search_running = false;               // with already_booted: the TV-satellite search is running
    double start_az = 180.0, start_el = 45.0;  // true position at start (mapped into the wrap window)
    std::string link_path;                     // if non-empty: symlink to the pty slave, removed on destruction
    std::uint32_t seed = 1;                    // RSSI noise, search wander, fault injection (garbage, drops)
    LineFaults line_faults;                    // initial line faults (see Emulator fault injection)

    // --- unknown-behaviour switches -----------------------------------------------------
    // Every switch below is listed in sim/README.md with its CLI flag, evidence and alternatives.
    bool echo = true;  // §6.1 (G2: strong evidence), §3.1 / §14 (others: hints only)
    LineEnding line_ending = LineEnding::crlf;
    // Unset: the captured G2's `Invalid command` on the captured G2 (§6.3), elsewhere `Unknown
    // command` (§14 HAL0.4: undocumented, INVENTED). Empty = print nothing.
    std::optional<std::string> unknown_command_reply;
    OutOfRange out_of_range = OutOfRange::clamp;
    // Printed instead of moving when out_of_range == reject. INVENTED default.
    std::string out_of_range_reply = "Angle out of range";
    // §14 G2.3: `a <id> <deg>` ack + prompt right away (motion continues in the background)
    // or only when the commanded motion has finished.
    MoveAck move_ack = MoveAck::immediate;
    // false: a position query issued while moving is answered once the dish has stopped.
    bool answer_position_while_moving = true;
    AzReport az_report = AzReport::displayed;
    // §2 / §3.5: any byte received during `g` aborts it (the Trav'ler README). Unset = the
    // variant's default: yes, except on the 2003 Carryout, whose scan client sends `q` right after
    // every 1-degree `g` and still maps the sky (§8.5, §11.1, §14 CO.3).
    std::optional<bool> g_aborts_on_input;
    // §6.5 vs §14 G2.2: `q` at TRK> kills the shell (console dead until power cycle: birdcage, who
    // had a G2 on the bench). false = "harmless": the prompt is reprinted, as Davidson's home.py
    // needs (it sends `q` first and succeeds only if every reply ends in `>`, §6.6). Counted as a
    // hazard either way.
    G2RootQ g2_root_q = G2RootQ::kill;
    G2Console g2_console = G2Console::captured;
    // G2 with already_booted: axes calibrated (true) or reading INT_MAX until `h` (false), §6.4.
    bool g2_homed = true;
    // Does boot homing run when NVS 20 (Disable Tracker Proc) is TRUE? Unset: the console's answer,
    // no on the captured G2 (its boot log has no homing, §6.2), yes on the reconstructed one.
    std::optional<bool> g2_boot_homes;
    // After a boot that does not home: do the axes keep their calibration (positions read as before
    // the boot) or read INT_MAX until `h` (the predecessor's claim, §6.2)? The capture shows no
    // `a` before its `h *`, so it is open. Unset: yes on the captured G2, no on the reconstructed.
    std::optional<bool> g2_boot_calibrated;
    // Seconds from power-on to the captured G2's `TRK>` (§6.2: about 10 s; where in the boot the
    // time goes is not captured: the emulator spends it before `GPS Not Found`).
    double g2_boot_seconds = 10.0;
    // Settling error in the direction of travel (§6.4: +0.01 AZ, +0.05 EL outward, -0.02/-0.06 on
    // return, a capture of four moves). Off by default: see sim/README.md "Switches".
    bool g2_overshoot = false;
    HomeReport home_report = HomeReport::wrap_limits;
    PromptStyle prompt_style = PromptStyle::named;  // Trav'ler, Pro, Carryout 2003 only
    // §14 HAL0.1: a space after `>`? Davidson's G2 transcript shows typed text right after the
    // prompt (`TRK>nvs`, §6.1): no space.
    bool prompt_space = false;
    BootMarker hal205_boot_marker = BootMarker::no_gps;            // §4.2
    TravlerBootMoves travler_boot_moves = TravlerBootMoves::park;  // §3.2, §14 HAL0.9
    // The boot's moves (a Trav'ler's calibration, the 2003 Carryout's) as a firmware task of their
    // own: when they end against the ready line or the first prompt is not given (§3.2, §5.2, §8.2,
    // §14 HAL0.9). Unset: the boot waits for each move, and its ready line and shell come once the
    // dish rests. S: the boot goes on S seconds after its first move starts, without waiting for the
    // moves, which run to their end while the console answers: the search stop does not stop them,
    // and a move commanded meanwhile queues behind them. A boot that homes (the G2's) waits for its
    // homing either way: its axes are uncalibrated until it ends.
    std::optional<double> boot_moves_overlap;
    // Seconds the dish stands still between two of the boot's moves (a calibration that pauses
    // between its legs). INVENTED, as the moves themselves.
    double boot_move_pause = 0.0;
    bool hal205_accepts_mot = false;  // §14 HAL2.05.4: does `mot` work besides `motor`?
    // §14 Pro.2: does `q` at the ODU root return to the IDU console? The Pro client sends
    // `odu`, `q`, CR, `mot` (§5.6), which only works if it does not.
    bool pro_q_at_odu_root_returns_to_idu = false;
    // §8.2: the 2003 Carryout's search cannot be stopped from the console; it ends by itself
    // (calibration + search take 10-15 min). Simulated seconds of wandering.
    double carryout_search_seconds = 600.0;
    // §14 CO.1: period of the `g` live line, unknown. INVENTED 4 Hz; carryout_rotor.py needs one
    // within 1 s and 100 bytes (§8.4).
    double carryout_live_line_period = 0.25;
    double rssi_floor = 401.0;  // §11.2 (Davidson ~400 with lnbdc odu; birdcage ~500, §14 G2.14)
    // Azimuth target mapping (see AzMapping). Default nearest: the only reading under which the
    // travel beyond 360 (Trav'ler 0..455, G2 446.66, §1, §6.4) is of use to the 0..360 targets
    // every upstream client sends; §2 describes the wrap point at 0 as something that
    // "sometimes" happens, i.e. a fault, and §3.4 as "usually 360 or 455".
    AzMapping az_mapping = AzMapping::nearest;
    double az_wrap_point = 0.0;  // wrap_manager: display azimuth of the wrap point (0 = north)
    // Position replies (§14 HAL0.3, G2.10): decimals (every client needs at least one, Appendix C),
    // leading spaces (birdcage's demo indents by 4, §6.3), Trav'ler field layout.
    int position_decimals = 2;
    // Unset: 4 on the captured G2 (`    Angle[0] = 180.00`, §6.3), 0 elsewhere.
    std::optional<int> position_indent;
    TravlerPositionLayout travler_position_layout = TravlerPositionLayout::one_line;

    // `?` listing (§6.3, §3.3, §8.3). Upper case applies to the command words only.
    // Unset: `available` on the captured G2, `described` elsewhere.
    std::optional<HelpLayout> help_layout;
    bool help_upper_case = false;
    // §6.3 names G2 commands that its listing is not known to show: MOT `l` (list motors) and DVB
    // `dis` (channel parameters). Whether `?` lists them is unknown; on, the shell accepts them
    // and `?` leaves them out, the case birdcage-probe --deep exists for. Off: unknown commands.
    bool unlisted_commands = false;

    HelpGrammar help_grammar;  // with help_layout == generated

    // --- console shape drawn by the dialect generator (dialect.hpp) ------------------------
    // Extra boot lines and silences (empty: the documented boot log only).
    std::vector<ExtraBootLine> boot_extra;
    // Decorations of every prompt, on every variant (a product tag before the documented text,
    // e.g. "WG " or "[G2]", and marks after its '>', e.g. "$"): the documented prompt text stays
    // (§6.3 for the G2), what a firmware build adds around it is open (§14 HAL0.1).
    std::string prompt_prefix;
    std::string prompt_suffix;

    // --- motor dynamics (docs/firmware.md §3.4, §6.4; docs/tracking.md §1.4) ---------------
    // The variant's speeds and acceleration are the defaults. Only the G2's are read from its
    // NVS; the Trav'ler's are one fit to two whole-move timings, which a motor that starts late
    // and then runs faster meets as well, so each part is open and can be chosen here.
    MotorDynamics motor;

    // --- boot timing and unsolicited output (§14 HAL0.5, G2.7) ---------------------------
    // Simulated seconds between boot lines. INVENTED: no source gives boot timing.
    double boot_line_gap = 0.05;
    // All dish output leaves at the variant's baud rate, 10 bits per byte, in SIMULATED time
    // (LineFaults::pace_baud is the real-time wire version). Off: a reply is there at once, as
    // Console tests expect; a real UART always paces.
    bool pace_at_line_rate = false;
    // Simulated seconds between the completion line and the late boot lines after it (G2:
    // `Boot Complete`, then `Loc Startup: IDU NOT Present`, §6.2 items 3-4). Input arriving after
    // the completion line is kept and answered once the late lines and the boot prompt are out;
    // input before it is lost (nothing reads the UART yet, INVENTED).
    double late_boot_line_delay = 0.05;
    // Input dropped for this many simulated seconds after the last boot line. 0: accepted at
    // once, as travler_init.py needs (it writes right after `NoGPS`, §3.6); nothing in the notes
    // supports a deaf window, it exists to try a client against one.
    double boot_input_drop = 0.0;
    // One more line after the last documented boot line (G2: after `Loc Startup: ...`; Trav'ler:
    // after `NoGPS`/`No LNB Voltage`), before the shell's prompt. Empty (default): none. §6.2
    // says items 1-9 may be abridged and §14 HAL0.5 / G2.7 leave the full boot log open, so a
    // line no client knows may follow the completion marker.
    std::string after_boot_line;
    // An unsolicited line every idle_line_period simulated seconds once booted (0 = never, the
    // default: the 2003 Carryout shows a "blank screen" on connect, §8.1, and no G2 transcript
    // shows periodic output). The G2 does print asynchronous lines (`Loc Startup: ...` after
    // boot, `AZ MOTOR STALLED`, §6.2, §6.3), so a stray line at idle is plausible.
    std::string idle_line;
    double idle_line_period = 0.0;

    // --- the sky (docs/sky.md) ---------------------------------------------------------------
    // How the dish's axes sit against the sky (§1): the beam points at dish_to_sky(mount, axes).
    // The console reports the axes; the G2's RSSI is the sky's where the beam points.
    Mount mount;
    // Set: the G2's RSSI is the real sky over this station (the geostationary belt and the Sun,
    // sky.hpp); unset: the real scan's sky (sim/data/g2-ku-skyscan).
    std::optional<Station> station;
    // UTC (Unix seconds) of emulated time 0: the sky clock is epoch + simulated seconds, so
    // time_scale speeds the Sun up with everything else. Unset: the wall clock at construction.
    std::optional<double> epoch;
    // Emulator: the truth CSV (sim/README.md "The sky") is written to this file as the dish moves.
    // Console: rows are kept for take_truth() when it is non-empty.
    std::string truth_path;

    // --- transcript replay ------------------------------------------------------------------
    // With a mode other than off, the dish answers from this transcript (recorded timing divided
    // by time_scale) instead of the model; the constructor throws TranscriptError if it is bad.
    std::string transcript_path;
    ReplayMode replay = ReplayMode::off;

    // Console traffic observer, called from the console thread. from_client: bytes the client
    // wrote; otherwise bytes the dish sent.
    std::function<void(bool from_client, std::string_view bytes)> trace;
};

struct Pose {
    double az;
    double el;
};
struct Sample {
    double t;
    double az;
    double el;
};
// One row of the truth file: where the dish's axes are and where its beam points on the sky.
struct TruthRow {
    double t;               // simulated seconds (UTC: epoch + t)
    double dish_az;         // the azimuth axis, displayed (0..360)
    double dish_el;         // the elevation axis
    double sky_az, sky_el;  // dish_to_sky(mount, axes), azimuth 0..360
    bool moving;            // a move is running or queued
};

class Console;

// RAII: the constructor opens the pty and starts the console thread; the destructor stops the
// thread, closes the pty and removes the symlink. All accessors are thread-safe.
class Emulator {
public:
    explicit Emulator(Options);
    ~Emulator();
    Emulator(const Emulator&) = delete;
    Emulator& operator=(const Emulator&) = delete;

    // link_path if given, else /dev/pts/N (a new N after reconnect(), hence by value).
    std::string device_path() const;
    Pose true_position() const;                        // displayed az in [0,360), el
    double true_mechanical_az() const;                 // az including cable-wrap turns
    double move_time(int axis, double degrees) const;  // Console::move_time()
    bool moving() const;
    bool search_running() const;
    std::vector<Sample> history() const;  // true position over simulated time
    // Command lines the core's hazard rule names (docs/firmware.md §15) sent outside a move request,
    // and the state-dependent hazards (moves on unhomed axes, the Pro above 75°); at most one per line.
    unsigned hazards_received() const;
    std::vector<std::string> hazard_commands() const;    // the line of each, in order
    std::vector<std::string> received_commands() const;  // every complete line, in order (empty lines included)
    double sim_time() const;
    // Where the beam points on the sky: Options::mount applied to the axes (sky azimuth 0..360).
    AzEl beam_direction() const;
    double epoch() const;  // UTC of simulated time 0 (Options::epoch, or the wall clock at start)
    // Reboot, also mid-move: motion stops dead, boot log (and boot moves), the search restarts
    // where the variant's does, menu at root, deadlocks cleared. Counts as an injected fault.
    void power_cycle();
    bool shell_alive() const;  // false after a G2 root `q` or an ADC `scan` deadlock

    // --- fault injection (docs/reliability.md), all thread-safe -------------------------------------
    // Random bytes (seeded by Options::seed) queued on the line now, behind dish output already
    // queued, as an idle unbiased RS-422 bus produces (§6.1 MAX490 without fail-safe biasing).
    void inject_garbage(std::size_t bytes);
    // Continuous garbage at this many bytes per real second whenever the dish has nothing queued
    // to send (0 = off).
    void set_idle_noise(double bytes_per_second);
    // Swapped RX pair (§6.1): every byte the dish sends arrives bit-inverted (~b); input is still
    // parsed normally.
    void set_inverted_polarity(bool on);
    // Swapped TX pair (§6.1): the dish silently ignores input (bytes never reach the console).
    void set_ignore_input(bool on);
    // Each byte the dish sends is lost with probability p (seeded RNG, one draw per byte).
    void set_drop_probability(double p);
    // 0 = unpaced. Otherwise each byte occupies the line for 10 bits at this baud rate of REAL
    // time (a wire property: not scaled by time_scale); no byte reaches the client before its
    // last bit would have.
    void set_output_pacing(int baud);
    // The dish sends nothing for this many simulated seconds and reads nothing either: input is
    // buffered and answered afterwards; motion and time go on. Overlapping stalls extend.
    void stall_output(double sim_seconds);
    // Adapter unplugged: the pty is closed (the client's fd sees POLLHUP, read returns 0/EIO,
    // writes fail), the symlink is removed, the /dev/pts node goes away. The dish keeps running;
    // what it prints meanwhile is lost.
    void hang_up();
    // Adapter back: a new pty; with link_path the symlink now points at the new slave (and
    // device_path() stays the link). No-op while connected.
    void reconnect();
    bool connected() const;
    // Axis 0 = AZ, 1 = EL: the move of that motor in progress, or its next one, stalls halfway to
    // its target: the axis stops dead, queued moves are dropped and the console prints
    // `AZ MOTOR STALLED` / `EL MOTOR STALLED` (§6.3). Other values are ignored.
    void inject_motor_stall(int motor);
    // One-shot faults injected so far: inject_garbage, stall_output, power_cycle, hang_up,
    // inject_motor_stall calls.
    unsigned faults_injected() const;
    FaultCounters fault_counters() const;
    LineFaults line_faults() const;  // the current continuous faults

    // Replay only. The diff at the first unexpected command (strict mode), escaped, with the
    // transcript line number; nullopt while the session follows the transcript.
    std::optional<std::string> replay_failure() const;
    bool replay_complete() const;   // every transcript chunk was matched or sent
    bool replay_fell_back() const;  // lenient mode handed over to the model console

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace birdcage::sim
