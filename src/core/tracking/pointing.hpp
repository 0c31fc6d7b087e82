// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Predictive pointing: infer the satellite's motion from the stream of client targets and aim the
// dish where the satellite will be, instead of where the client last said it was.
//
// Why the backend has to infer it: the Hamlib rotator API carries no time tags or rates, and the
// clients that drive it reveal the trajectory only sparsely. Gpredict (docs/tracking.md §5,
// docs/tracking.md §3.2) sends a target only when the read-back differs from the satellite by
// more than its threshold (default 5°), and then sends a point *ahead* of the satellite (a lead of
// up to one threshold). A dish that jumps to each target therefore sweeps from one threshold
// ahead to one threshold behind: ~threshold/√3 RMS whatever the backend does (≈2.9° at 5°).
//
// What this estimator does with each target T_k arriving at t_k:
//   * velocity: least-squares slope of the recent targets (a constant lead cancels out);
//   * lead: the client's lead is learned from "lag" events: when the dish followed the previous
//     target and fell behind, the client fires once the satellite is one threshold past the dish
//     and sends a point one threshold further, so T - dish ≈ 2 v τ along the track. The lead is
//     kept as a threshold in degrees (Gpredict's box is per axis, in plain degrees) and turned
//     into a time τ = threshold / |v|∞ for the current rate;
//   * the satellite is then at S(t) = T_k - v τ + v (t - t_k), extrapolated for a bounded time.
// A target that repeats the last one, or lands far from the prediction, restarts the estimate
// (the client stopped, parked or switched satellites): the dish then goes to that target and
// holds it, with no overshoot.
//
// Pure and clock-free: the caller passes the times (RotatorService uses the controller's clock,
// which runs k× faster against the emulator).
#pragma once

#include <chrono>
#include <cstddef>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "base/azel.hpp"
#include "base/plain_types.hpp"
#include "tracking/orbit_model.hpp"
#include "tracking/wrap.hpp"

namespace birdcage {

enum class PointingMode {
    none,        // go to each target as sent
    leapfrog,    // the upstream clients' overshoot of a lagging axis (docs/firmware.md §12.1) (Controller applies it)
    predictive,  // TargetPredictor below
};

std::optional<PointingMode> pointing_mode_from_name(std::string_view name);
std::string_view pointing_mode_name(PointingMode mode);

struct PredictorSettings {
    // Least-squares window for the velocity (targets older than this are dropped from the fit,
    // but the last two are always kept). Long enough to average Gpredict's lead quantisation
    // (a quarter cycle, 0.25 s) over several samples.
    double fit_window_s = 30.0;
    // A gap longer than this between targets restarts the estimate (the client stopped).
    double max_gap_s = 120.0;
    // How long past the last target the motion is extrapolated: this many times the last
    // interval between targets, bounded below and above.
    double extrapolate_intervals = 3.0;
    double min_extrapolation_s = 10.0;
    double max_extrapolation_s = 90.0;
    // A target farther than this from the predicted target restarts the estimate.
    double restart_gate_deg = 20.0;
    // Above this elevation the azimuth rate changes quickly (keyhole): azimuth is extrapolated
    // at most zenith_extrapolation_s past the last target.
    double zenith_guard_el = 75.0;
    double zenith_extrapolation_s = 2.0;
    // Above this on-sky rate two targets are two pointings, not a satellite (LEO: <= 1.2 deg/s,
    // docs/tracking.md §2.1).
    double max_sky_rate_dps = 3.0;
    // Below this on-sky rate the target counts as stationary.
    double stationary_dps = 0.002;
    // What makes a stream of targets a satellite rather than manual pointing (rotctl, a jogging
    // TUI, a sky scan stepping a grid; docs/tracking.md §7): the motion is extrapolated only once
    // this many targets in a row (since the last restart) lie on a smooth track (the fit window's
    // targets within max_track_residual_deg RMS of the fitted curve, on the sky) at an on-sky rate
    // a LEO satellite can have (<= 1.16 deg/s, docs/tracking.md §2.1; the margin is for the
    // client's lead quantisation).
    std::size_t min_track_targets = 3;
    double max_satellite_sky_rate_dps = 1.5;
    double max_track_residual_deg = 0.5;
    // ... and that never turns by more than this between successive steps of at least
    // min_turn_step_deg on the sky (a quadratic in az/el fits a serpentine's reversal).
    double max_track_turn_deg = 60.0;
    double min_turn_step_deg = 0.2;
    // Until this many targets in a row over this long, the extrapolation stops at the last target:
    // a few manual steps at a satellite's pace are not yet a pass, and manual pointing must end
    // exactly where it was sent.
    std::size_t established_track_targets = 3;
    double established_track_s = 20.0;
    // Follow the satellite's orbit fitted to the targets (orbit_model.hpp) whenever the fit is
    // trusted, to the end of the pass; the local estimate above stays the fallback (the first
    // targets, manual pointing). Conf `pass_model` (docs/tracking.md §6).
    bool use_pass_model = true;
    OrbitModelSettings orbit;
};

struct Prediction {
    AzEl position;         // azimuth in [0, 360)
    double az_rate = 0.0;  // deg/s of the (unwrapped) azimuth
    double el_rate = 0.0;
    bool moving = false;  // false: hold `position` (stationary or extrapolation expired)
};

class TargetPredictor {
public:
    explicit TargetPredictor(PredictorSettings settings = {});

    // A new client target at time `t`; `dish` is the position the client compared the satellite
    // with (the one `p` last answered before the target; else the backend's reading), if known.
    void observe(Clock::time_point t, AzEl target, std::optional<AzEl> dish);
    // A position answered to the client (`p`) at time `t`: every one, not only the last before a
    // target, because which one a client compared the satellite with depends on its I/O timing.
    void note_reported(Clock::time_point t, AzEl position);
    void reset();
    // The dish's elevation limits: a client set up with them clamps its targets there, and a dish
    // held on one is off the satellite's track: its gap to an unclamped target is read by the
    // client's send rule, not along the track.
    void set_dish_limits(double el_min, double el_max);

    // The estimated satellite direction at time `t` (t may lie ahead of now).
    std::optional<Prediction> predict(Clock::time_point t) const;
    // The rest of the pass above the dish's elevation floor from `t` on, as the trusted orbit
    // foresees it, for the cable-wrap branch; none without a trusted orbit.
    std::optional<wrap::PassAhead> pass_ahead(Clock::time_point t) const;

    // For logs and tests.
    // The client's lead (its threshold, degrees): as learnt from the dish, else as the trusted
    // orbit fitted it (a dish held on its floor while the client sends every cycle learns none),
    // or where the orbit's targets show the dish's gaps misled (a client without look-ahead).
    std::optional<double> lead_threshold_deg() const {
        if (pass_model_in_use() && (!lead_threshold_ || orbit_.lead_from_targets())) {
            return orbit_.lead_deg();
        }
        return lead_threshold_;
    }
    // How coarse the client's targets are, for the steering's deadband: half the gap the dish's lag
    // shows (Gpredict: its threshold; a client without look-ahead: half its step), else the trusted
    // orbit's lead. Not corrected by the orbit as the lead is: a client that sends a target every
    // 5 deg without look-ahead leads by nothing, but its steps still ask for a coarse deadband
    // (with the lead's 0, the G2 made 624 motor starts on iss-45 at 5 deg).
    // A client's steps show its coarseness too: one without look-ahead steps by its threshold
    // whatever the dish did, while on a dish the orbit leads its gaps are nothing (the G2 then fell
    // to its minimum deadband and started its motors 617 times on iss-45 at 5 deg, k = 5). So where
    // the lead in use is under a fifth of the client's half step (a client that leads by L steps
    // by about 2L, rarely much more), the half step stands for the coarseness.
    std::optional<double> client_coarseness_deg() const {
        const std::optional<double> gaps = lead_threshold_       ? lead_threshold_
                                           : pass_model_in_use() ? orbit_.lead_deg()
                                                                 : std::nullopt;
        if (client_without_look_ahead()) {
            return std::max(gaps.value_or(0.0), *half_step_);
        }
        return gaps;
    }
    // The client's steps show no look-ahead: client_coarseness_deg() is then half its step, half
    // the threshold it sends by (a client that leads by its threshold L steps by about 2L, and
    // its coarseness is L).
    // A lead the dish's gaps taught and the trusted orbit kept (the targets did not refute it) is
    // the client's own, however far apart its targets lie: while the dish is steered ahead, real
    // Gpredict at 0.5 deg sends only now and then, and its steps are then the satellite's motion
    // meanwhile, not its threshold. Read as a client without look-ahead, it got the cost per start's
    // coarse deadband (2 deg on the sky), and its loop's error rose from 0.25 to 0.7 deg RMS
    // (docs/tracking.md §6).
    bool client_without_look_ahead() const {
        const std::optional<double> lead = lead_threshold_deg();
        const bool lead_confirmed = pass_model_in_use() && lead_threshold_ && !orbit_.lead_from_targets() &&
                                    *lead_threshold_ >= min_confirmed_lead_deg;
        return !lead_confirmed && half_step_ && half_steps_.size() >= min_half_steps && lead &&
               *lead < no_look_ahead_lead_share * *half_step_;
    }
    bool pass_model_in_use() const { return settings_.use_pass_model && orbit_.trusted(); }
    const OrbitModel& orbit() const { return orbit_; }
    std::string describe() const;

private:
    struct Sample {
        double t;   // seconds since origin_
        double az;  // unwrapped, continuous with the previous sample
        double el;
    };
    double seconds(Clock::time_point t) const;
    // predict(), or with hold_at_last_target false the bare extrapolation (what the next target is
    // checked against: a client that went quiet may resume along the same track).
    std::optional<Prediction> estimate(Clock::time_point t, bool hold_at_last_target) const;
    void fit();
    std::vector<AzEl> sample_directions() const;
    // keep_orbit: the orbit model expected this target (a new pointing for the local estimate only).
    void restart(double t, AzEl target, bool keep_orbit);
    // Gpredict's send rule against the positions the client read back: a target it could not have
    // sent shows a client without look-ahead, whose lead is none (docs/tracking.md §6).
    void question_lead_by_send_rule(double t);

    PredictorSettings settings_;
    Clock::time_point origin_{};
    bool has_origin_ = false;
    std::deque<Sample> samples_;
    double az_rate_ = 0.0, el_rate_ = 0.0;  // at the anchor
    double az_accel_ = 0.0, el_accel_ = 0.0;
    bool have_rate_ = false;
    bool held_ = false;                     // the last target repeated the one before: the client holds still
    std::optional<double> lead_threshold_;  // learned client threshold, degrees (per axis)
    std::deque<double> lead_observations_;
    struct Reported {
        double t;  // seconds since origin_
        AzEl position;
    };
    std::deque<Reported> reported_;  // the positions answered lately, oldest first
    int no_lead_evidence_ = 0;       // targets Gpredict's send rule could not have sent
    // Half the client's step between targets sent apart (on the faster axis), a low median.
    std::optional<double> half_step_;
    std::deque<double> half_steps_;
    static constexpr double no_look_ahead_lead_share = 0.2;
    static constexpr std::size_t min_half_steps = 3;
    static constexpr double min_confirmed_lead_deg = 0.25;  // Gpredict's smallest useful threshold, halved
    // The estimated satellite position at anchor_t_ (the last target minus the lead).
    double anchor_t_ = 0.0, anchor_az_ = 0.0, anchor_el_ = 0.0;
    double last_interval_s_ = 0.0;
    // Targets since the last restart (a restart is a new pointing).
    std::size_t track_targets_ = 0;
    double track_start_t_ = 0.0;
    OrbitModel orbit_;
    double dish_el_min_ = 0.0, dish_el_max_ = 90.0;
};

}  // namespace birdcage
