// The antenna: initialisation, position, one-axis-at-a-time moves, stop, leap-frog.
#pragma once

#include <chrono>
#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <utility>

#include "birdcage/az_mapping.hpp"
#include "birdcage/azel.hpp"
#include "birdcage/clock.hpp"
#include "birdcage/errors.hpp"
#include "birdcage/log.hpp"
#include "birdcage/session.hpp"
#include "birdcage/transport.hpp"
#include "birdcage/variants.hpp"
#include "birdcage/wrap.hpp"

namespace birdcage {

struct ControllerOptions {
    VariantId variant;
    bool leapfrog = true;
    std::optional<double> el_min, el_max;          // user overrides, never beyond the variant's mechanical/firmware limits
    std::optional<double> az_min, az_max;          // user azimuth range (0..360 display degrees): targets are clamped into it
    // How the firmware maps an azimuth command onto its travel (az_mapping.hpp), as the user states
    // it; nullopt (auto): learnt from where the dish goes.
    std::optional<azmap::Mapping> az_mapping;
    std::chrono::milliseconds boot_timeout{15 * 60 * 1000};
    bool skip_init = false;                         // user says the dish is ready (already in the motor menu)
    bool detect = false;                            // RotatorService: identify the variant at start (auto)
    std::string detection_note;                     // how the variant was identified (shown by describe())
    int line_baud = 0;                              // the rate the port was opened at (describe()); 0 = unknown
    LogSink log;
    // The dish's time (clock.hpp): motion bookkeeping (leg budgets, poll pacing) runs on it;
    // I/O deadlines on the serial line stay real.
    DishClock clock;
};

class Controller {   // single-threaded; the lead's RotatorService calls it from one worker thread
public:
    Controller(Transport& transport, ControllerOptions options);

    Status initialize();
    // initialize() again after a reboot, hang-up or lost sync, waiting at most `boot_budget` for a
    // booting dish (bounded slices: the caller retries). Legs in flight are dropped.
    Status reinitialize(std::chrono::milliseconds boot_budget);
    // True when the controller must be initialised (again): never initialised, the dish printed
    // boot output since, or the console answered from a menu other than the one initialize() left
    // it in: the only sign of a reboot on firmware that prints no boot lines (Pro).
    bool needs_reinit() const;
    // The firmware's fault line (`AZ MOTOR STALLED`) that ended the last leg, once; empty if none.
    std::string take_fault() { return std::exchange(leg_fault_, std::string()); }
    Result<AzEl> query_position();    // asks the dish now; updates last_position(); az in [0, 360)
    // Validates, clamps, picks the azimuth's cable-wrap branch, leap-frogs, queues legs. No I/O.
    // `target.az` may be 0..360 or -180..180 (any finite value is taken modulo 360); the backend
    // chooses the mechanical branch (see choose_azimuth_branch()). `az_rate_dps` is the caller's
    // estimate of the target's azimuth rate (deg/s, sign = direction of motion; 0 = unknown or
    // stationary): it lets a pass start on the branch with room for the whole pass.
    Status set_target(AzEl target, double az_rate_dps = 0.0);
    Status service();                 // one pump step (~every 50 ms)
    void cancel_pending();            // drops legs not yet sent; aborts a running `g` where input aborts it
    Status home();                    // runs the variant's homing commands (blocking); unsupported if none
    AzEl park_position() const { return {profile_.park_az, profile_.park_el}; }
    bool unhomed() const { return unhomed_; }
    bool tracker_enabled() const { return tracker_enabled_; }
    bool idle() const;
    std::optional<AzEl> last_position() const { return last_position_; }
    std::optional<AzEl> current_target() const { return current_target_; }
    // The controller's estimate of the mechanical azimuth (cable-wrap turns included, in the
    // variant's az_min..az_max coordinates); nullopt before the first reading.
    std::optional<double> mechanical_azimuth() const { return mech_az_; }
    // The single-axis move in flight, for a position model between polls: the axis goes from
    // `from` (its last reading, taken at `from_at`) to `to`, display degrees.
    struct LegMotion {
        Axis axis = Axis::azimuth;
        double from = 0.0, to = 0.0;
        Clock::time_point from_at{};
        Clock::time_point sent_at{};
    };
    std::optional<LegMotion> leg_motion() const;
    // The mechanical azimuth current_target() was put on (before leapfrog); nullopt without a target.
    std::optional<double> target_mechanical_azimuth() const { return target_mech_az_; }
    const FirmwareProfile& profile() const { return profile_; }
    // What is known of the firmware's azimuth mapping (stated, learnt, still possible).
    const azmap::Learner& az_mapping() const { return az_learner_; }
    std::string describe() const;
    // The cable-wrap state: travel, the mechanical azimuth estimate and how its branch is known
    // (the start assumption), the target's branch. Not (yet) part of describe(), whose text the
    // transcript golden files (sim/transcripts/*.chk) pin.
    std::string describe_wrap() const;

    // True while a leg has been sent and not yet arrived: the console must stay in the motor menu.
    bool leg_in_flight() const { return in_flight_.has_value(); }
    // The one way into a submenu other than the motor menu: from the motor menu through the root
    // into `menu`, `work` there, then back into the motor menu whatever `work` returned. Refused
    // (Errc::busy) while a leg is in flight; legs not yet sent stay queued.
    Status in_submenu(std::string_view menu, const std::function<Status(ConsoleSession&)>& work);

    double el_min() const { return el_min_; }
    double el_max() const { return el_max_; }
    bool initialised() const { return initialised_; }

private:
    struct Leg {
        bool combined = false;         // `g az el` (both axes) instead of `a <axis> <deg>`
        Axis axis = Axis::azimuth;
        AzEl target;                   // the commanded value(s); for a single axis only its field counts
        // Azimuth legs: the mechanical azimuth this leg commands (target.az is its display form)
        // and the one the move ends at; they differ while waypoints lead there (wrap::next_waypoint).
        double mech_az = 0.0;
        double final_mech_az = 0.0;
        int waypoints_left = 4;        // bounds the waypoint legs per target (3 span any window)
        // Azimuth legs, for learning the mapping: where the axis started and the range its readings
        // swept; path_known while the readings came close enough together to follow it.
        double from_mech = 0.0, lowest = 0.0, highest = 0.0;
        bool path_known = false;
        std::optional<double> expected_end;   // where the learnt mapping now says it goes (if not mech_az)
        Clock::time_point sent_at{};
        std::chrono::milliseconds budget{0};   // estimated time x 2 + margin
        std::optional<double> last_seen;       // the axis' position at the previous poll
        Clock::time_point last_change{};
        // Combined `g` legs: a live position line was printed; the dish was not already at the target.
        bool live_seen = false;
        bool needs_motion = false;
    };

    Clock::time_point now() const;
    Status run_steps(std::span<const ConsoleStep> steps, std::string_view purpose);
    Status initialize_within(std::chrono::milliseconds boot_budget);
    Status wait_for_boot();
    Status leave_submenus();
    Status check_homing();
    Status check_tracker_disabled();
    Status send_leg(Leg& leg);
    Status service_axis_leg();
    void plan_azimuth_leg(Leg& leg);
    Status service_combined_leg();
    void finish_leg(std::string_view how);
    void finish_combined_leg(std::string_view how);
    Status lose_sync(const std::string& why);
    Result<AzEl> note_live_output(std::span<const std::string> lines);
    double leg_distance(const Leg& leg) const;
    Result<AzEl> ask_position(std::chrono::milliseconds timeout);
    void note_azimuth_reading(double reported);
    void update_mechanical_azimuth(double reported);
    void observe_azimuth_leg(Leg& leg, bool at_rest);
    void replan_after_surprise();
    std::optional<double> branch_reference() const;
    double choose_azimuth_branch(AzEl wanted, const std::optional<AzEl>& previous, double az_rate_dps);
    void forget_target();

    const FirmwareProfile& profile_;
    ControllerOptions options_;
    ConsoleSession session_;
    double el_min_, el_max_;
    bool initialised_ = false;
    bool unhomed_ = false;
    bool tracker_enabled_ = false;
    bool tracker_checked_ = false;      // G2 NVS 20 "Disable Tracker Proc?" read FALSE at init
    bool fault_reported_ = false;       // the last position reply carried a fault line (stall)
    bool position_estimated_ = false;   // last_position_ comes from commands, not a readback
    std::optional<AzEl> last_position_;
    std::optional<Clock::time_point> last_position_at_;
    std::optional<AzEl> current_target_;
    std::optional<double> commanded_az_, commanded_el_;   // values last sent (or in flight); az mechanical
    // Cable wrap (wrap.hpp). The dish may report its azimuth as displayed (0..360) or mechanical
    // (firmware.md §14 G2.4): the controller keeps its own mechanical estimate, unwrapping each
    // reading to the branch nearest it.
    wrap::Window az_window_;          // the variant's mechanical travel
    wrap::Window az_usable_;          // less the limit margins: never commanded outside
    azmap::Travel az_travel_;         // az_window_ and how numbers are sent for it
    azmap::Learner az_learner_;
    std::optional<double> mech_az_;   // mechanical azimuth estimate (see mechanical_azimuth())
    std::optional<Clock::time_point> mech_az_at_;   // when mech_az_ was last read
    bool az_report_mechanical_ = false;   // readings outside 0..360 proved the dish reports mechanically
    int beyond_display_readings_ = 0;     // consecutive readings outside 0..360 (2 prove it)
    bool recheck_branch_ = false;         // after (re)initialisation: keep mech_az_ only if the dish still reads it
    std::optional<double> target_mech_az_;   // mechanical azimuth of current_target_
    std::optional<int> pass_direction_;      // azimuth direction of the pass being followed (+1/-1)
    std::deque<Leg> pending_;
    std::optional<Leg> in_flight_;
    Clock::time_point last_poll_{};
    unsigned move_count_ = 0;
    std::chrono::milliseconds boot_budget_{0};   // wait_for_boot()'s bound for this initialisation
    std::string leg_fault_;                      // see take_fault()
    std::string motor_menu_;                     // the session's menu at the end of initialize()
    // This console prints live positions while `g` runs (a fact about the firmware: kept across
    // re-initialisations); only then can their absence mean anything.
    bool live_output_proven_ = false;
    bool sync_lost_ = false;                     // the console is not where it was left (needs_reinit())
};

}  // namespace birdcage
