// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The antenna: initialisation, position, moves, stop, leap-frog, homing (see the class comment).
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "base/azel.hpp"
#include "base/clock.hpp"
#include "base/errors.hpp"
#include "base/log.hpp"
#include "base/option_range.hpp"
#include "console/console_events.hpp"
#include "console/session.hpp"
#include "console/transport.hpp"
#include "dish/dish_state.hpp"
#include "dish/menu_navigator.hpp"
#include "dish/move_driver.hpp"
#include "firmware/variants.hpp"
#include "tracking/az_mapping.hpp"
#include "tracking/wrap_tracker.hpp"

namespace birdcage {

struct ControllerOptions {
    // What a user may set: elevation limits (further narrowed to the variant's), the azimuth range
    // in display degrees (its ends are the defaults: the whole circle) and the boot wait.
    static constexpr OptionRange el_range{0.0, 90.0, 0.01};
    static constexpr OptionRange az_range{0.0, 360.0, 0.01};
    static constexpr OptionRange boot_timeout_range_s{0.0, 3600.0, 1.0};

    VariantId variant;
    bool leapfrog = true;
    std::optional<double> el_min, el_max;  // user overrides, never beyond the variant's mechanical/firmware limits
    std::optional<double> az_min, az_max;  // user azimuth range (0..360 display degrees): targets are clamped into it
    // How the firmware maps an azimuth command onto its travel (az_mapping.hpp), as the user states
    // it; nullopt (auto): learnt from where the dish goes.
    std::optional<azmap::Mapping> az_mapping;
    // The longest opening waits for the console (RotatorService::start(), rot_open): a line silent
    // that long fails the open; a dish heard booting is initialised in the background instead.
    std::chrono::milliseconds boot_timeout{60 * 1000};
    bool skip_init = false;      // user says the dish is ready (already in the motor menu)
    bool detect = false;         // RotatorService: identify the variant at start (auto)
    std::string detection_note;  // how the variant was identified (shown by describe())
    int line_baud = 0;           // the rate the port was opened at (describe()); 0 = unknown
    bool line_is_pty = false;    // a pseudo-terminal (the emulator): no rate applies (describe())
    LogSink log;
    // What the controller learns from the console's replies, as values (console_events.hpp), in
    // the order it was read; unset: nothing is reported.
    ConsoleEventSink console_events;
    // The dish's time (clock.hpp): motion bookkeeping (leg budgets, poll pacing) runs on it;
    // I/O deadlines on the serial line stay real.
    DishClock clock;
};

// The antenna, composed of parts with one job each: the console synchroniser and the menu
// navigator bring the console to the motor menu; the variant's move driver (move_driver.hpp) turns
// targets into commands and follows them; the wrap tracker keeps the mechanical azimuth; the
// position reader turns replies into DishState. What is left here: initialisation, target
// validation and clamping, leapfrog, homing, the idle checks, and describe().
// The dish as describe() and the backend's get_info name it: the variant's display name (its
// firmware, where the name carries it), and "(auto-detected)" when detection chose it.
std::string dish_identity(const FirmwareProfile& profile, bool auto_detected);

class Controller {  // single-threaded; RotatorService calls it from one worker thread
public:
    Controller(Transport& transport, ControllerOptions options);
    Controller(const Controller&) = delete;  // the parts hold references to each other
    Controller& operator=(const Controller&) = delete;
    ~Controller();

    Status initialize();
    // A controller built over a port reopened after a hang-up takes over what the one before it
    // knew of the dish (before its initialize()): the last position, the cable-wrap turns and
    // azimuth mapping learnt, and the motors' learnt pace, start-up delay and step time. An unplugged adapter does not move the dish, so the branch it was on
    // holds; the first reading after the re-initialisation still rechecks it (a dish that
    // rebooted meanwhile has moved, and its branch is assumed afresh).
    void carry_over(const Controller& before);
    // initialize() again after a reboot, hang-up or lost sync, waiting at most `boot_budget` for a
    // booting dish (bounded slices: the caller retries). Legs in flight are dropped.
    Status reinitialize(std::chrono::milliseconds boot_budget);
    // True when the controller must be initialised (again): never initialised, the dish printed
    // boot output since, the console answered from a menu other than the one initialize() left
    // it in (the only sign of a reboot on firmware that prints no boot lines, Pro), or the move
    // driver saw the console is not where it was left (the 2003 Carryout's silent reboot).
    bool needs_reinit() const;
    // The firmware's fault line (`AZ MOTOR STALLED`) that ended the last leg, once; empty if none.
    std::string take_fault() { return std::exchange(state_.fault, std::string()); }
    Result<AzEl> query_position();  // asks the dish now; updates last_position(); az in [0, 360)
    // The idle poll: whether the console answers, and the position where the variant can report it
    // at rest (query_position()). Where it cannot (the 2003 Carryout, docs/firmware.md 8.3) the
    // console is asked for a sign of life without a word that moves: a bare line ending, or `?`
    // where the line ending draws nothing (the synchroniser's two pokes); any text it prints is an
    // answer, and last_position() stays the last one known. Ok when the console answered.
    Status poll_at_rest();
    // Validates, clamps, leap-frogs, and has the move driver queue legs. No I/O.
    // `target.az` may be 0..360 or -180..180 (any finite value is taken modulo 360); the backend
    // chooses the mechanical branch (WrapTracker::choose_branch()). `az_rate_dps` is the caller's
    // estimate of the target's azimuth rate (deg/s, sign = direction of motion; 0 = unknown or
    // stationary): it lets a pass start on the branch with room for the whole pass. `ahead`: the
    // rest of the pass as a trusted orbit foresees it (exact room, and when to unwind).
    Status set_target(AzEl target, double az_rate_dps = 0.0,
                      const std::optional<wrap::PassAhead>& ahead = std::nullopt);
    Status service();       // one pump step (~every 50 ms)
    void cancel_pending();  // drops legs not yet sent; aborts a running `g` where input aborts it
    // Homing (Hamlib reset) without blocking: start_home() queues the variant's home commands
    // (unsupported if none) and service() drives them, sending each and then reading the console
    // a short slice per call until its prompt returns (the G2's `h` holds the shell until the
    // axis is homed), bounded per command; last_position() is read again at the end. While it
    // runs the console is busy: idle() and query_position() say so, targets set meanwhile wait.
    Status start_home();
    bool homing() const { return homing_.has_value(); }
    Status home();  // start_home(), then service() until it ends (blocking)
    bool unhomed() const { return state_.unhomed; }
    // After an initialisation that failed: the console was heard booting meanwhile, so it may yet
    // come up (a silent line may be nothing at all).
    bool boot_heard() const { return session_.reboot_seen(); }
    // False also while the dish, seen moving since initialisation (or moving on its own while a leg
    // waited), has not come to rest. Not yet known at rest, it is idle but its legs wait.
    bool idle() const;
    // How long a small step takes this dish, as its own legs timed it (MoveDriver).
    std::optional<double> learnt_step_seconds(Axis axis) const;
    // The motors' start-up delays and paces, as the legs timed them (MoveDriver).
    MotorTiming learnt_motor() const;
    std::optional<AzEl> last_position() const { return state_.last_position; }
    // When last_position() was read or inferred (the options' dish clock); none before the first.
    std::optional<Clock::time_point> last_position_at() const { return state_.last_position_at; }
    std::optional<AzEl> current_target() const { return state_.target; }
    // The controller's estimate of the mechanical azimuth (cable-wrap turns included, in the
    // variant's az_min..az_max coordinates); nullopt before the first reading.
    std::optional<double> mechanical_azimuth() const { return wrap_.mechanical(); }
    using LegMotion = birdcage::LegMotion;
    MovingAxes moving_axes() const;
    const FirmwareProfile& profile() const { return profile_; }
    // dish_identity(), then the dish's state (the most urgent first: not initialised, axes NOT
    // homed, the TV search on, then homing, moving or idle), then the details. The identity and
    // the state lead because some clients see only the start: Hamlib's netrotctl (rotctl -m 2)
    // reads get_info into 64 bytes, 63 characters.
    std::string describe() const;
    // The cable-wrap state: travel, the mechanical azimuth estimate and how its branch is known
    // (the start assumption), the target's branch. Not part of describe(); the transcript golden
    // files read the same facts through wrap_tracker().
    std::string describe_wrap() const { return wrap_.describe(); }

    // True while a leg has been sent and not yet arrived: the console must stay in the motor menu.
    bool leg_in_flight() const;
    // The one way into a submenu other than the motor menu: from the motor menu through the root
    // into `menu`, `work` there, then back into the motor menu whatever `work` returned. Refused
    // (Errc::busy) while a leg is in flight; legs not yet sent stay queued.
    Status in_submenu(std::string_view menu, const std::function<Status(ConsoleSession&)>& work);

    double el_min() const { return el_min_; }
    double el_max() const { return el_max_; }
    bool initialised() const { return initialised_; }

    // What describe() words, as values, for output that machines compare (the transcript golden
    // files, sim/transcripts/*.chk): rewording describe() must not change them.
    bool auto_detected() const { return options_.detect; }
    int line_baud() const { return options_.line_baud > 0 ? options_.line_baud : profile_.baud; }
    const std::string& console_menu() const { return session_.menu(); }
    const std::string& console_prompt() const { return session_.last_prompt(); }
    bool position_estimated() const { return state_.position_estimated; }
    bool tracker_enabled() const { return tracker_enabled_; }
    bool leapfrog() const { return options_.leapfrog; }
    const WrapTracker& wrap_tracker() const { return wrap_; }

private:
    // A position query (`a`): ~60 bytes even at 57600 baud take ~11 ms.
    static constexpr std::chrono::milliseconds query_timeout{2000};

    Clock::time_point now() const;
    Status initialize_within(std::chrono::milliseconds boot_budget);
    // Ok(true): the dish has just printed its ready line and is at its root, its TV search starting.
    Result<bool> wait_for_boot();
    Status open_motor_menu();
    void warn_if_unhomed() const;
    Status check_tracker_disabled();
    void forget_target();
    bool moved_on_its_own(const AzEl& before, const AzEl& now) const;
    Status service_homing();  // controller_homing.cpp, with start_home() and home()
    Status finish_homing();
    // The dish at rest since initialisation: every reading until they agree over a span.
    void note_start_reading(const AzEl& reading);
    Status service_start_motion();

    const FirmwareProfile& profile_;
    ControllerOptions options_;
    ConsoleSession session_;
    double el_min_, el_max_;
    DishState state_;
    WrapTracker wrap_;
    PositionReader reader_;
    MenuNavigator menus_;
    std::unique_ptr<MoveDriver> driver_;
    bool initialised_ = false;
    struct HomingRun {
        std::size_t next = 0;          // index into profile_.home_commands
        bool awaiting_prompt = false;  // home_commands[next] was sent; its prompt has not come back
        Clock::time_point sent_at{};
    };
    std::optional<HomingRun> homing_;
    // The poke that drew an answer from a console without a position query at rest ("" or "?"),
    // once one has; until then poll_at_rest() tries the line ending, then `?`.
    std::optional<std::string_view> sign_of_life_poke_;
    bool tracker_enabled_ = false;  // G2 NVS 20 "Disable Tracker Proc?" read FALSE (describe())
    bool tracker_checked_ = false;
    std::chrono::milliseconds boot_budget_{0};  // wait_for_boot()'s bound for this initialisation
    // Whether the dish is at rest after initialisation is unknown until its readings agree over a
    // span of dish time (a stopped TV search brakes, a boot move may still run, and two readings
    // taken a moment apart agree on a dish at speed). Until then it is polled and moves wait; seen
    // moving, it must stay still for longer than a motor that starts late leaves it still between
    // two moves its firmware has queued. Its cable-wrap branch is judged where it rests.
    struct StartRest {
        AzEl still;  // the earliest reading of the run that agrees with the latest
        Clock::time_point still_at{};
        AzEl last;                   // the latest reading
        bool moving = false;         // two readings differed
        Clock::time_point since{};   // when it was first seen moving
        Clock::time_point polled{};  // the latest poll
        StartRest(AzEl reading, Clock::time_point t) : still(reading), still_at(t), last(reading), polled(t) {}
        void start_moving(Clock::time_point t) {
            moving = true;
            since = polled = t;
        }
    };
    std::optional<StartRest> start_rest_;
    // The target to plan again once the dish rests: its legs were dropped when it moved on its own.
    bool replan_at_rest_ = false;
    // The dish was moved from wherever it was, still moving on its own (a search the firmware keeps
    // running): its motion no longer stops the legs.
    bool moves_regardless_ = false;
    void enter_start_motion(const AzEl& reading);
    void end_start_rest();
    void move_regardless();
    std::string motor_menu_;  // the session's menu at the end of initialize()
};

}  // namespace birdcage
