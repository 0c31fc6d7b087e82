// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The satellite's orbit fitted to the client's targets, for following a pass far beyond the last
// target (docs/tracking.md §6).
//
// Why an orbit: at Gpredict's default 5° threshold a target comes every 15–40 s, and when the dish
// tracks well none comes at all (silence means "still within the threshold"). Anything fitted to
// the shape of the track on the sky needs many targets before it holds; a circular orbit about the
// Earth's centre has only four unknowns, all of them physical, and Kepler's third law ties the
// satellite's speed to its radius, so two targets already pin it down.
//
// The model, in the site's east-north-up frame: the Earth's centre lies one Earth radius below the
// site; the satellite runs on a circle of radius r about it at the Kepler rate ω = √(μ/r³); the
// site turns with the Earth (its latitude sets the axis; without one the Earth is taken as still
// and describe() says so). Unknowns: the satellite's geocentric direction at the reference time
// (2), its heading there (1), its altitude (1).
//
// What a target says (Gpredict's look-ahead, docs/tracking.md §5): an unclamped target is the
// satellite's exact direction at its arrival time plus the client's lead (the time the satellite
// takes to move one threshold on its faster axis; the threshold comes from the caller, which
// learns it). A target clamped to the dish's elevation floor or cap says only the azimuth. A
// target below the horizon is the client waiting at the AOS azimuth: the model's track must rise
// there.
//
// Fitting: the two-point circular solution (one unknown, the radius: the arc between two directions
// must be what the Kepler rate covers in the time between them) gives the start, Levenberg–Marquardt
// refines it on every target held. The model is trusted while the residual, the altitude and the
// span of the targets say so; each new target is first checked against the prediction (an
// innovation above the gate refits from scratch, and a fit that still fails starts over: another
// satellite, a park).
//
// Pure and clock-free: times are seconds on the caller's clock.
#pragma once

#include <array>
#include <cstddef>
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "base/azel.hpp"
#include "base/option_range.hpp"

namespace birdcage {

struct OrbitModelSettings {
    static constexpr OptionRange latitude_range{-90.0, 90.0, 0.01};

    // Site latitude (degrees north); none: the fit takes the Earth as not turning.
    std::optional<double> latitude_deg;
    // The dish's elevation limits: a target on one of them was clamped there by the client.
    double el_floor = 0.0, el_cap = 90.0;
    // A target is computed on the client's timer tick and sent by its I/O loop up to 0.8 s later
    // (Gpredict, docs/tracking.md §5): on average this much before it arrives.
    double client_send_delay_s = 0.4;
    // Altitudes a tracked LEO satellite has; outside them the fit is not a satellite.
    double min_altitude_km = 150.0, max_altitude_km = 2000.0;
    // Trust: this many unclamped targets, over this arc of sky and this much time, within this RMS
    std::size_t min_exact_targets = 3;
    // ... or this many, where a target clamped to the dish's limits (above the horizon) checks the
    // fit: two directions and their times fix the four unknowns, and the clamped azimuth, which a
    // fit of a manual jog or the wrong lead misses, is the test (docs/tracking.md §6).
    std::size_t min_exact_targets_checked = 2;
    double min_arc_deg = 2.0;
    // (the time as long as a manual track needs to count as one: docs/tracking.md §7)
    double min_span_s = 20.0;
    // A pass's track turns gently between targets; a scan's serpentine or a user's jogging do not.
    double max_turn_deg = 60.0;
    // (RMS over the scatter a target's timing gives it at the satellite's rate, and in degrees).
    double max_normalised_residual = 3.0;
    double max_residual_deg = 1.5;
    // ... and, when the caller does not know the client's lead, with the fitted one this certain
    // and from this many unclamped targets (a few targets fit a wrong lead and a wrong altitude
    // together and claim to be sure of both).
    double max_lead_sigma_deg = 0.3;
    std::size_t min_exact_targets_fitted_lead = 8;
    // A new target farther than this (degrees, or gate_residuals × the fit's RMS if larger) from
    // where the trusted model expected it means the model is wrong or the client changed its mind.
    double innovation_gate_deg = 2.0;
    double gate_residuals = 5.0;
    // Targets kept for the fit (the oldest are thinned out first) and how old they may be.
    std::size_t max_targets = 120;
    double window_s = 1200.0;
};

struct OrbitPoint {
    AzEl position;         // azimuth in [0, 360)
    double az_rate = 0.0;  // deg/s
    double el_rate = 0.0;
};

class OrbitModel {
public:
    explicit OrbitModel(OrbitModelSettings settings = {});
    // The dish's elevation limits (what a client configured as the README says clamps to).
    void set_dish_limits(double el_floor, double el_cap);

    void clear();
    // A client target arriving at time t (seconds). `lead_hint_deg`: the client's lead (its
    // threshold, per axis, degrees; 0: the targets are the satellite's direction when sent) as the
    // caller learnt it; none: it is fitted with the orbit, and trusted once the targets pin it
    // down. Returns false when a trusted model did not expect the target (the
    // innovation gate); the target is kept either way and the model refitted.
    bool add(double t, AzEl target, std::optional<double> lead_hint_deg);
    // The caller learnt the client's lead anew after add() (from the gap the target just showed):
    // an untrusted fit is judged again with it, rather than one target later.
    void relead(std::optional<double> lead_hint_deg);
    // The caller found the client's send rule to be no look-ahead (TargetPredictor): the orbit
    // holds a lead of none from now until it is cleared, whatever the hint.
    void take_lead_as_none();

    bool trusted() const { return trusted_; }
    std::size_t targets() const { return targets_.size(); }
    // Where the satellite is at time t; nullopt until a fit exists (trusted or not).
    std::optional<OrbitPoint> predict(double t) const;
    // Where the client's next unclamped target would be if it were sent at time t.
    std::optional<AzEl> expected_target(double t) const;
    // Altitude (km) of the current fit, and the client's lead it fitted (or was given).
    std::optional<double> altitude_km() const;
    std::optional<double> lead_deg() const;
    // The standard error of a lead fitted with the orbit; 0 for one given (or none yet).
    double lead_sigma_deg() const { return orbit_ && !lead_in_fit() ? orbit_->lead_sigma_deg : 0.0; }
    // The targets themselves showed the client's lead to be other than the caller's hint.
    bool lead_from_targets() const {
        return orbit_ && lead_hint_deg_ && (lead_fitted_despite_hint_ || lead_none_despite_hint_ || no_look_ahead_);
    }
    // When the satellite sets below `el` after time t (within `within_s`), for the caller's horizon.
    std::optional<double> time_below(double t, double el, double within_s) const;
    // The part of the current (or next, within `within_s`) pass above elevation `el` from time t
    // on: where and when it starts (t itself if the satellite is above `el` then), its culmination,
    // when it ends, and the azimuth it turns on the way (signed, + clockwise; unwrapped along the
    // track, so a pass across north is one sweep). For the cable-wrap branch of a whole pass.
    struct PassSpan {
        double start_t = 0.0, start_az = 0.0;
        double top_t = 0.0, top_el = 0.0;
        double end_t = 0.0;
        double sweep_deg = 0.0;
    };
    std::optional<PassSpan> pass_above(double t, double el, double within_s) const;
    // For logs: the fit's parameters and residual, or why it is not trusted.
    const std::string& describe() const { return description_; }

    // The orbit's parameters, exposed for tests: geocentric direction at t_ref as tangent-plane
    // offsets (x, y), heading, altitude.
    struct Orbit {
        double t_ref = 0.0;
        double x = 0.0, y = 0.0, heading = 0.0, altitude_km = 500.0;
        double lead_deg = 0.0;        // the client's lead (threshold, degrees), fitted when not given
        double lead_sigma_deg = 0.0;  // its standard error (0 when given)
    };

    // How the client made its targets: its threshold (0: no look-ahead) and the elevation limits it
    // clamps to.
    struct ClientView {
        double threshold = 0.0;
        double min_el = 0.0, max_el = 90.0;
    };

private:
    ClientView client_view() const;
    enum class Kind { exact, clamped, before_rise };
    struct Target {
        double t;
        AzEl direction;
        Kind kind;
    };
    void refit(bool from_scratch);
    bool initialise();
    struct FitResidual {
        double rms_deg = 0.0;     // of the unclamped targets
        double normalised = 0.0;  // the same over the scatter expected of each (1: as expected)
        std::size_t exact_count = 0;
        // The clamped targets above the horizon, which check a fit of few unclamped ones: their
        // RMS miss over the scatter expected of each, and how many.
        double check_normalised = 0.0;
        std::size_t check_count = 0;
        // Exact and check targets together, as the one figure two leads are compared by.
        double overall() const;
    };
    FitResidual refine(Orbit& orbit, int iterations) const;
    FitResidual refine(Orbit& orbit, int iterations, std::optional<double> fixed_lead) const;
    void question_lead();
    void judge();
    std::vector<AzEl> exact_directions() const;
    // The same, ordered by where the fitted track passes nearest each (not by when it was sent).
    std::vector<AzEl> exact_directions_along_track() const;

    OrbitModelSettings settings_;
    std::deque<Target> targets_;
    std::optional<double> lead_hint_deg_;
    bool lead_fitted_despite_hint_ = false;  // question_lead() found the targets contradict the hint
    bool lead_none_despite_hint_ = false;    // ... and fit no lead at all clearly better
    bool no_look_ahead_ = false;             // take_lead_as_none()
    // The lead the fit holds: the hint, none, or fitted (nullopt), as question_lead() decided.
    std::optional<double> lead_in_fit() const;
    std::size_t next_lead_question_ = 0;  // exact targets at which to question it next (when many)
    // The client's elevation limits as its targets show them: the dish's until one lies beyond.
    double client_min_el_ = 0.0, client_max_el_ = 90.0;
    std::optional<Orbit> orbit_;
    FitResidual residual_;
    bool trusted_ = false;
    std::string description_ = "no targets";
};

}  // namespace birdcage
