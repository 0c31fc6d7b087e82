// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// OrbitModel on the SGP4 passes of bench/passes (site 45° N, bench/generate_passes.py): exact
// directions, then a Gpredict-like threshold client with its look-ahead (docs/tracking.md §5,
// testbed/gpredict_client.cpp), and the refusals: manual pointing, a jump to another satellite.
// Pure and deterministic: no threads, no sleeping; every time is built here.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "base/azel.hpp"
#include "error_stats.hpp"
#include "tracking/orbit_model.hpp"
#include "tracking/pointing.hpp"

using namespace birdcage;

namespace {

double two_decimals(double x) {
    return std::round(x * 100.0) / 100.0;
}

double sky_angle(AzEl a, AzEl b) {
    const double d = M_PI / 180.0;
    const double c =
        std::sin(a.el * d) * std::sin(b.el * d) + std::cos(a.el * d) * std::cos(b.el * d) * std::cos((a.az - b.az) * d);
    return std::acos(std::clamp(c, -1.0, 1.0)) / d;
}

// A pass from bench/passes (columns t,az,el; '#' comment lines), interpolated linearly.
struct TruePass {
    std::string name;
    std::vector<double> t, az, el;

    static TruePass load(const std::string& name) {
        TruePass pass;
        pass.name = name;
        std::ifstream in(std::string(BIRDCAGE_SOURCE_DIR) + "/bench/passes/" + name + ".csv");
        REQUIRE(in.good());
        std::string line;
        while (std::getline(in, line)) {
            if (line.empty() || line[0] == '#' || line[0] == 't') {
                continue;
            }
            double t = 0, az = 0, el = 0;
            char comma = 0;
            std::istringstream row(line);
            row >> t >> comma >> az >> comma >> el;
            pass.t.push_back(t);
            pass.az.push_back(az);
            pass.el.push_back(el);
        }
        REQUIRE(pass.t.size() > 100);
        return pass;
    }

    AzEl at(double time) const {
        const auto upper = std::upper_bound(t.begin(), t.end(), time);
        const std::size_t i = std::clamp<std::size_t>(static_cast<std::size_t>(upper - t.begin()), 1, t.size() - 1) - 1;
        const double f = (time - t[i]) / (t[i + 1] - t[i]);
        return {normalize_azimuth(az[i] + f * azimuth_difference(az[i], az[i + 1])), el[i] + f * (el[i + 1] - el[i])};
    }
    double rise() const {
        for (std::size_t i = 0; i < t.size(); ++i) {
            if (el[i] >= 0.0) {
                return t[i];
            }
        }
        return t.front();
    }
};

using Errors = birdcage::test::ErrorStats;

const char* const pass_names[] = {"iss-20", "iss-45", "iss-60", "iss-70", "iss-85",
                                  "sso-20", "sso-45", "sso-70", "sso-85"};
constexpr double site_latitude = 45.0;  // bench/generate_passes.py

// Errors of the model's prediction against the pass from `from` to the end (satellite above the
// horizon), every second.
Errors prediction_errors(const OrbitModel& model, const TruePass& pass, double from) {
    Errors errors;
    for (double s = from; s < pass.t.back(); s += 1.0) {
        const AzEl truth = pass.at(s);
        if (truth.el < 0.0) {
            continue;
        }
        const auto p = model.predict(s);
        REQUIRE(p.has_value());
        errors.add(sky_angle(p->position, truth));
    }
    return errors;
}

}  // namespace

TEST_CASE("orbit model: three directions a minute after rise predict the rest of each pass") {
    for (const char* name : pass_names) {
        const TruePass pass = TruePass::load(name);
        for (const bool with_latitude : {true, false}) {
            OrbitModelSettings settings;
            if (with_latitude) {
                settings.latitude_deg = site_latitude;
            }
            OrbitModel model(settings);
            const double rise = pass.rise();
            // Sent as computed, with no look-ahead (lead 0).
            const double delay = settings.client_send_delay_s;
            for (const double after : {30.0, 45.0, 60.0}) {
                const AzEl seen = pass.at(rise + after - delay);
                model.add(rise + after, {two_decimals(seen.az), two_decimals(seen.el)}, 0.0);
            }
            const Errors errors = prediction_errors(model, pass, rise + 60.0);
            std::printf("%-7s latitude %-3s trusted %d alt %.0f  RMS %.3f max %.3f  | %s\n", name,
                        with_latitude ? "yes" : "no", model.trusted(), model.altitude_km().value_or(-1), errors.rms(),
                        errors.max, model.describe().c_str());
            INFO(name << (with_latitude ? " with" : " without") << " the latitude: " << model.describe());
            // Measured when written: with the latitude 0.13-1.9 deg RMS, 0.27-4.3 max, altitude
            // within 17 km of the elements' (420 and 820 km); without, 1.6-14 deg RMS.
            if (with_latitude) {
                CHECK(errors.rms() < 3.0);
                CHECK(errors.max < 7.0);
                CHECK(std::fabs(*model.altitude_km() - (name[0] == 'i' ? 420.0 : 820.0)) < 30.0);
            } else {
                CHECK(model.describe().find("no latitude") != std::string::npos);
            }
        }
    }
}

namespace {

// A Gpredict-like client (docs/tracking.md §5): its timer at `now` and what it sends, if anything.
// Its target is the satellite clamped to its limits [min_el, max_el] (before AOS: the AOS azimuth
// at its lowest elevation); it is sent when the dish is more than `threshold` off on either axis
// (plain differences), leading the satellite (bisection to a quarter cycle), with two decimals,
// 0-0.8 s after the tick (its I/O loop; `jitter_state` draws the delay).
struct SentTarget {
    double arrival;
    AzEl target;
};

class GpredictLikeClient {
public:
    // look_ahead false: a simpler client (bench --client current) that sends the satellite's
    // direction as it is whenever it is more than `threshold` from its own last target.
    GpredictLikeClient(const TruePass& pass, double threshold, double min_el, double max_el, bool look_ahead = true)
        : pass_(pass),
          threshold_(threshold),
          min_el_(min_el),
          max_el_(max_el),
          aos_az_(pass.at(pass.rise()).az),
          end_(pass.t.back() - 1.0),
          look_ahead_(look_ahead) {}

    double aos_az() const { return aos_az_; }
    double end() const { return end_; }

    std::optional<SentTarget> tick(double now, AzEl dish) {
        const AzEl sat = pass_.at(now);
        AzEl set = sat.el < 0.0 ? AzEl{aos_az_, clamp_el(0.0)} : AzEl{sat.az, clamp_el(sat.el)};
        // Gpredict compares azimuths as plain numbers (docs/tracking.md §5); the simpler client
        // across north.
        const AzEl compared = look_ahead_ ? dish : last_sent_.value_or(AzEl{set.az + 180.0, set.el});
        const double az_off = look_ahead_ ? set.az - compared.az : azimuth_difference(compared.az, set.az);
        if (std::fabs(az_off) <= threshold_ && std::fabs(set.el - compared.el) <= threshold_) {
            return std::nullopt;
        }
        last_sent_ = set;
        if (sat.el > 0.0 && look_ahead_) {
            double delta = end_ - now, step = std::max(delta / 2.0, 1.0);
            AzEl future = set;
            while (step > 0.25) {
                future = pass_.at(now + delta);
                const bool too_far = future.el < 0.0 || std::fabs(set.az - future.az) > threshold_ ||
                                     std::fabs(set.el - future.el) > threshold_;
                delta += too_far ? -step : step;
                step /= 2.0;
            }
            set = {future.az, clamp_el(future.el)};
        }
        jitter_state_ = jitter_state_ * 1103515245u + 12345u;
        const double send_delay = 0.8 * static_cast<double>((jitter_state_ >> 8) % 1000u) / 1000.0;
        return SentTarget{now + send_delay, {two_decimals(set.az), two_decimals(set.el)}};
    }

private:
    double clamp_el(double el) const { return std::clamp(el, min_el_, max_el_); }

    const TruePass& pass_;
    double threshold_, min_el_, max_el_, aos_az_, end_;
    bool look_ahead_;
    std::optional<AzEl> last_sent_;
    std::uint32_t jitter_state_ = 1;
};

struct ClientRun {
    int targets = 0;
    Errors now_error;               // the model's satellite now against the truth, while trusted
    double trusted_from_el = 90.0;  // the satellite's elevation when the model was first trusted
    int seconds_untrusted = 0;      // above the floor
};

// The Gpredict-like client with its limits against a dish that goes to each target clamped to
// [floor, cap] at once; the orbit alone, as the target stream shapes it.
ClientRun run_client(const TruePass& pass, double threshold, double client_min_el, double client_max_el, double floor,
                     double cap, std::optional<double> lead_known) {
    OrbitModelSettings settings;
    settings.latitude_deg = site_latitude;
    settings.el_floor = floor;
    settings.el_cap = cap;
    OrbitModel model(settings);
    ClientRun run;
    GpredictLikeClient client(pass, threshold, client_min_el, client_max_el);
    AzEl dish{client.aos_az() + 40.0, floor};
    for (double now = pass.rise() - 60.0; now < client.end(); now += 1.0) {
        const AzEl sat = pass.at(now);
        if (const auto sent = client.tick(now, dish)) {
            model.add(sent->arrival, sent->target, lead_known);
            dish = {sent->target.az, std::clamp(sent->target.el, floor, cap)};
            ++run.targets;
        }
        if (sat.el < floor) {
            continue;
        }
        if (!model.trusted()) {
            ++run.seconds_untrusted;
            continue;
        }
        run.trusted_from_el = std::min(run.trusted_from_el, sat.el);
        run.now_error.add(sky_angle(model.predict(now)->position, sat));
    }
    return run;
}

}  // namespace

TEST_CASE("orbit model: the rest of a pass above the dish's floor, for its cable-wrap branch") {
    constexpr double floor_el = 18.0;  // the G2's
    for (const char* name : pass_names) {
        const TruePass pass = TruePass::load(name);
        OrbitModelSettings settings;
        settings.latitude_deg = site_latitude;
        OrbitModel model(settings);
        const double rise = pass.rise();
        for (const double after : {30.0, 45.0, 60.0}) {
            const AzEl seen = pass.at(rise + after - settings.client_send_delay_s);
            model.add(rise + after, {two_decimals(seen.az), two_decimals(seen.el)}, 0.0);
        }
        // The truth from the same moment: the azimuth it turns while above the floor.
        const double from = rise + 60.0;
        double true_sweep = 0.0, true_start = -1.0, true_end = -1.0;
        AzEl previous{};
        for (double s = from; s < pass.t.back(); s += 1.0) {
            const AzEl here = pass.at(s);
            if (here.el < floor_el) {
                if (true_start >= 0.0) {
                    break;
                }
                continue;
            }
            if (true_start < 0.0) {
                true_start = s;
            } else {
                true_sweep += azimuth_difference(previous.az, here.az);
            }
            true_end = s;
            previous = here;
        }
        const auto span = model.pass_above(from, floor_el, 1800.0);
        std::printf("%-7s pass above %.0f: sweep %.1f (truth %.1f), from %.0f s to %.0f s (truth %.0f to %.0f)\n", name,
                    floor_el, span ? span->sweep_deg : 0.0, true_sweep, span ? span->start_t - from : -1.0,
                    span ? span->end_t - from : -1.0, true_start - from, true_end - from);
        if (true_start < 0.0) {
            continue;  // a pass that stays below the floor needs no room
        }
        REQUIRE(span);
        INFO(name << ": " << model.describe());
        // Measured when written: the sweep within 0.4 deg, the end within 8 s.
        CHECK(std::fabs(span->sweep_deg - true_sweep) < 10.0);
        CHECK(std::fabs(span->end_t - true_end) < 30.0);
        CHECK(span->top_el > floor_el);
    }
}

TEST_CASE("orbit model: a Gpredict-like client's look-ahead targets give the satellite within tenths of a degree",
          "[figures]") {
    struct Setting {
        double threshold;
        double client_min_el, client_max_el;
        std::optional<double> lead;
    };
    for (const Setting s : {Setting{5.0, 18, 65, 5.0}, Setting{5.0, 0, 90, 5.0}, Setting{0.5, 18, 65, 0.5},
                            Setting{0.5, 0, 90, 0.5}, Setting{5.0, 18, 65, std::nullopt}}) {
        double sum_rms = 0.0;
        // Wide limits send a target every cycle below the floor, hundreds per pass, each refitting
        // the orbit: four passes (a low and a zenith pass of each orbit) keep the sanitizer build's
        // run of this test within a couple of minutes.
        const bool wide = s.client_min_el < 18.0;
        const std::vector<const char*> names =
            wide ? std::vector<const char*>{"iss-20", "iss-85", "sso-20", "sso-85"}
                 : std::vector<const char*>(std::begin(pass_names), std::end(pass_names));
        for (const char* name : names) {
            const TruePass pass = TruePass::load(name);
            const ClientRun run = run_client(pass, s.threshold, s.client_min_el, s.client_max_el, 18.0, 65.0, s.lead);
            std::printf(
                "thr %.1f limits %2.0f-%2.0f lead %-4s %-7s targets %3d untrusted %3d s, trusted from el %4.1f, RMS "
                "%.3f max %.3f\n",
                s.threshold, s.client_min_el, s.client_max_el, s.lead ? "yes" : "no", name, run.targets,
                run.seconds_untrusted, run.trusted_from_el, run.now_error.rms(), run.now_error.max);
            INFO("threshold " << s.threshold << " client limits " << s.client_min_el << "-" << s.client_max_el
                              << (s.lead ? " lead known " : " lead unknown ") << name);
            if (!s.lead) {
                // Nobody told it the lead: the model fits it, and is trusted only once the targets
                // pin it down (on the two 20 deg passes they never do: too few above the floor).
                CHECK((run.now_error.n == 0 || run.now_error.rms() < 1.0));
                continue;
            }
            // Measured when written (with the client's 0-0.8 s send delay): 0.02-0.37 deg RMS per
            // pass, 0.69-0.75 on the two zenith passes at 5 deg with wide limits; trusted from the
            // dish's floor on most passes, at the latest from el 43.
            CHECK(run.now_error.n > 0);
            CHECK(run.now_error.rms() < 1.0);
            CHECK(run.trusted_from_el < 45.0);
            sum_rms += run.now_error.rms();
        }
        if (s.lead) {
            CHECK(sum_rms / static_cast<double>(names.size()) < 0.35);
        }
    }
}

TEST_CASE("orbit model: manual pointing and a jump to another satellite are not an orbit") {
    OrbitModelSettings settings;
    settings.latitude_deg = site_latitude;
    OrbitModel model(settings);
    SECTION("a single target has no fit") {
        model.add(0.0, {120.0, 30.0}, std::nullopt);
        CHECK_FALSE(model.trusted());
        CHECK_FALSE(model.predict(10.0).has_value());
    }
    SECTION("manual pointing back and forth") {
        const AzEl points[] = {{100, 20}, {140, 40}, {110, 25}, {180, 10}, {90, 60}, {130, 30}};
        double t = 0.0;
        for (const AzEl p : points) {
            model.add(t, p, std::nullopt);
            t += 20.0;
            CHECK_FALSE(model.trusted());
        }
        INFO(model.describe());
    }
    SECTION("a sky scan's grid steps") {
        double t = 0.0;
        for (double el = 20.0; el <= 40.0; el += 10.0) {
            for (double az = 100.0; az <= 160.0; az += 10.0) {
                model.add(t, {az, el}, std::nullopt);
                t += 5.0;
                INFO(model.describe());
                CHECK_FALSE(model.trusted());
            }
        }
    }
    SECTION("a pass, then another satellite elsewhere") {
        const TruePass pass = TruePass::load("iss-45");
        const double rise = pass.rise();
        for (double after = 60.0; after <= 180.0; after += 10.0) {
            const AzEl seen = pass.at(rise + after - settings.client_send_delay_s);
            CHECK(model.add(rise + after, {two_decimals(seen.az), two_decimals(seen.el)}, 0.0));
        }
        REQUIRE(model.trusted());
        CHECK_FALSE(model.add(rise + 190.0, {30.0, 50.0}, 0.0));
        CHECK_FALSE(model.trusted());
        CHECK(model.targets() == 1);
    }
}

namespace {

const Clock::time_point t0 = Clock::time_point{} + std::chrono::hours(1000);

Clock::time_point at(double seconds) {
    return t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

// TargetPredictor fed by the Gpredict-like client above (dish limits 18-65, a dish that goes to
// each target): the satellite now and `ahead` seconds later, as the predictor gives it.
struct PredictorRun {
    Errors now_error, ahead_error;
    Errors on_orbit_error;  // the satellite now, while the orbit is in use
    int seconds_on_orbit = 0, seconds_measured = 0;
};

PredictorRun run_predictor(const TruePass& pass, double threshold, bool use_orbit, double ahead, bool look_ahead = true,
                           std::optional<double>* lead = nullptr) {
    PredictorSettings settings;
    settings.use_pass_model = use_orbit;
    settings.orbit.latitude_deg = site_latitude;
    TargetPredictor predictor(settings);
    predictor.set_dish_limits(18.0, 65.0);
    PredictorRun run;
    GpredictLikeClient client(pass, threshold, 18.0, 65.0, look_ahead);
    AzEl dish{client.aos_az() + 40.0, 18.0};
    const double end = client.end();
    int targets = 0;
    for (double now = pass.rise() - 60.0; now < end; now += 1.0) {
        const AzEl sat = pass.at(now);
        if (const auto sent = client.tick(now, dish)) {
            predictor.observe(at(sent->arrival), sent->target, dish);
            dish = sent->target;
            ++targets;
        }
        if (sat.el < 18.0 || sat.el > 65.0 || targets < 3) {
            continue;
        }
        ++run.seconds_measured;
        run.seconds_on_orbit += predictor.pass_model_in_use() ? 1 : 0;
        run.now_error.add(sky_angle(predictor.predict(at(now))->position, sat));
        if (predictor.pass_model_in_use()) {
            run.on_orbit_error.add(sky_angle(predictor.predict(at(now))->position, sat));
        }
        if (pass.at(now + ahead).el > 18.0 && now + ahead < end) {
            run.ahead_error.add(sky_angle(predictor.predict(at(now + ahead))->position, pass.at(now + ahead)));
        }
    }
    if (lead) {
        *lead = predictor.lead_threshold_deg();
    }
    return run;
}

}  // namespace

TEST_CASE("orbit model: the predictor follows the orbit and beats its local estimate", "[figures]") {
    // Measured when written (mean over the 9 passes of each pass's RMS, the satellite now / 30 s
    // ahead): at 5 deg 1.71 / 5.3 against the local estimate's 2.81 / 8.1; at 0.5 deg 0.19 / 1.5
    // against 0.30 / 8.3. The orbit is in use 40-77% of the time at 5 deg (the first targets above
    // the floor come minutes apart), 89-97% at 0.5 deg.
    for (const double threshold : {5.0, 0.5}) {
        double orbit_now = 0.0, local_now = 0.0, orbit_ahead = 0.0, local_ahead = 0.0;
        for (const char* name : pass_names) {
            const TruePass pass = TruePass::load(name);
            const PredictorRun orbit = run_predictor(pass, threshold, true, 30.0);
            const PredictorRun local = run_predictor(pass, threshold, false, 30.0);
            std::printf(
                "predictor thr %.1f %-7s on the orbit %3.0f%% | orbit now %.2f/%.2f 30 s %.2f/%.2f | local now "
                "%.2f/%.2f 30 s %.2f/%.2f\n",
                threshold, name, 100.0 * orbit.seconds_on_orbit / std::max(1, orbit.seconds_measured),
                orbit.now_error.rms(), orbit.now_error.max, orbit.ahead_error.rms(), orbit.ahead_error.max,
                local.now_error.rms(), local.now_error.max, local.ahead_error.rms(), local.ahead_error.max);
            orbit_now += orbit.now_error.rms();
            local_now += local.now_error.rms();
            orbit_ahead += orbit.ahead_error.rms();
            local_ahead += local.ahead_error.rms();
        }
        INFO("threshold " << threshold << ": mean RMS now " << orbit_now / 9 << " vs " << local_now / 9
                          << ", 30 s ahead " << orbit_ahead / 9 << " vs " << local_ahead / 9);
        CHECK(orbit_now < 0.8 * local_now);
        CHECK(orbit_ahead < (threshold > 1.0 ? 0.8 : 0.3) * local_ahead);
    }
}

TEST_CASE("orbit model: a client without look-ahead is followed as sent, its lead learnt as none", "[figures]") {
    // A client that sends the satellite's direction as it is, each time it moved a threshold from
    // its last target (no look-ahead): what a new user may try before Gpredict. The dish's gaps
    // say it leads by half its threshold (2.5 deg at 5 deg); the orbit's targets say it does not.
    // Measured when written, at 5 deg: the lead 0.0-0.41 deg on every pass (2.5 before the orbit
    // could overrule the gaps), the satellite now 1.4-1.9 deg RMS (the local estimate 2.3-2.9; most
    // of what is left comes before the orbit is trusted); at 0.5 deg the lead 0.0-0.41 (the gaps'
    // 0.27-0.41 stand on 5 of 9 passes: there the lead's effect is within the targets' scatter)
    // and the satellite now 0.24-0.39 deg RMS (local 0.34-0.45).
    for (const double threshold : {5.0, 0.5}) {
        double orbit_now = 0.0, local_now = 0.0, lead_sum = 0.0;
        for (const char* name : pass_names) {
            const TruePass pass = TruePass::load(name);
            std::optional<double> lead;
            const PredictorRun orbit = run_predictor(pass, threshold, true, 30.0, false, &lead);
            const PredictorRun local = run_predictor(pass, threshold, false, 30.0, false);
            std::printf(
                "no look-ahead thr %.1f %-7s lead %.2f on the orbit %3.0f%% (there %.2f/%.2f) | orbit now %.2f/%.2f | "
                "local now %.2f/%.2f\n",
                threshold, name, lead.value_or(-1.0),
                100.0 * orbit.seconds_on_orbit / std::max(1, orbit.seconds_measured), orbit.on_orbit_error.rms(),
                orbit.on_orbit_error.max, orbit.now_error.rms(), orbit.now_error.max, local.now_error.rms(),
                local.now_error.max);
            orbit_now += orbit.now_error.rms();
            local_now += local.now_error.rms();
            lead_sum += lead.value_or(threshold);
        }
        INFO("threshold " << threshold << ": mean RMS now " << orbit_now / 9 << " vs " << local_now / 9
                          << ", mean lead " << lead_sum / 9);
        CHECK(orbit_now < local_now);
        if (threshold > 1.0) {
            CHECK(lead_sum / 9 < 0.2 * threshold);
        }
    }
}

TEST_CASE("orbit model: the predictor falls back for a jump and a stop") {
    PredictorSettings settings;
    settings.orbit.latitude_deg = site_latitude;
    TargetPredictor predictor(settings);
    predictor.set_dish_limits(18.0, 65.0);
    const TruePass pass = TruePass::load("iss-45");
    const double rise = pass.rise();
    // A client that sends where the satellite is every 10 s (no look-ahead), as it is sent.
    for (double after = 150.0; after <= 300.0; after += 10.0) {
        const AzEl seen = pass.at(rise + after - OrbitModelSettings{}.client_send_delay_s);
        predictor.observe(at(rise + after), {two_decimals(seen.az), two_decimals(seen.el)}, std::nullopt);
    }
    INFO(predictor.describe());
    REQUIRE(predictor.pass_model_in_use());
    CHECK(predictor.orbit().lead_deg().value() < 0.2);
    CHECK(sky_angle(predictor.predict(at(rise + 450.0))->position, pass.at(rise + 450.0)) < 0.5);

    SECTION("a jump (another satellite, a manual P) drops the orbit and holds the new target") {
        const AzEl elsewhere{30.0, 50.0};
        predictor.observe(at(rise + 305.0), elsewhere, std::nullopt);
        CHECK_FALSE(predictor.pass_model_in_use());
        const auto p = predictor.predict(at(rise + 300.0));
        REQUIRE(p.has_value());
        CHECK_FALSE(p->moving);
        CHECK(sky_angle(p->position, elsewhere) < 0.01);
    }
    SECTION("a stop forgets the pass") {
        predictor.reset();
        CHECK_FALSE(predictor.pass_model_in_use());
        CHECK_FALSE(predictor.predict(at(rise + 300.0)).has_value());
    }
    SECTION("after the pass sets the dish is held, not driven below the horizon") {
        const auto p = predictor.predict(at(pass.t.back() + 60.0));
        REQUIRE(p.has_value());
        CHECK_FALSE(p->moving);
    }
}

namespace {

// A client's targets fed to the orbit with the lead the dish's gaps taught (`hint`), as
// run_client() feeds them; `each` sees the model after every unclamped target, with their count.
template <typename Each>
void feed_hinted(const TruePass& pass, double threshold, bool look_ahead, double hint, Each each) {
    constexpr double floor_el = 18.0, cap_el = 65.0;  // the G2's
    OrbitModelSettings settings;
    // The held-out pass's site lies at 40 N (bench/generate_heldout_pass.py), the others' at 45.
    settings.latitude_deg = pass.name.rfind("heldout", 0) == 0 ? 40.0 : site_latitude;
    settings.el_floor = floor_el;
    settings.el_cap = cap_el;
    OrbitModel model(settings);
    GpredictLikeClient client(pass, threshold, floor_el, cap_el, look_ahead);
    AzEl dish{client.aos_az() + 40.0, floor_el};
    std::size_t unclamped = 0;
    for (double now = pass.rise() - 60.0; now < client.end(); now += 1.0) {
        const auto sent = client.tick(now, dish);
        if (!sent) {
            continue;
        }
        model.add(sent->arrival, sent->target, hint);
        dish = {sent->target.az, std::clamp(sent->target.el, floor_el, cap_el)};
        if (sent->target.el > floor_el && sent->target.el < cap_el) {
            ++unclamped;
            each(model, unclamped);
        }
    }
}

}  // namespace

TEST_CASE("orbit model: the gaps' lead is put against none from the third target, a client's own lead kept",
          "[figures]") {
    SECTION("a client without look-ahead, learnt from the gaps as leading by half its threshold") {
        // Its steps of 5 deg leave the dish 5 deg behind each new target, as a client leading by
        // 2.5 deg would: the targets tell the two apart from the third one above the floor on.
        // Measured when written: the lead 2.5 at the second target, 0.0 at each of the 28 from the
        // third on.
        const TruePass pass = TruePass::load("heldout-iss-60");
        feed_hinted(pass, 5.0, false, 2.5, [](const OrbitModel& model, std::size_t unclamped) {
            if (unclamped >= 3) {
                INFO("unclamped target " << unclamped << ": " << model.describe());
                CHECK(model.lead_from_targets());
                REQUIRE(model.lead_deg());
                CHECK(*model.lead_deg() < 0.5);
            }
        });
    }
    SECTION("Gpredict at 0.5 deg, the gaps having learnt a little more") {
        // The satellite moves on while a target is sent (0-0.8 s), so the gaps teach a lead a
        // little above the threshold. A lead under 1 deg is within a few targets' scatter of none:
        // put against none it was taken for none from the third target on these passes, and the
        // dish trailed the satellite by it. Measured when written: the hint's 0.6 on most targets,
        // a lead fitted freely (0.47-1.10) on the rest, none nowhere.
        for (const char* name : {"iss-45", "sso-45"}) {
            const TruePass pass = TruePass::load(name);
            feed_hinted(pass, 0.5, true, 0.6, [&](const OrbitModel& model, std::size_t unclamped) {
                if (unclamped >= 2) {
                    INFO(name << ", unclamped target " << unclamped << ": " << model.describe());
                    REQUIRE(model.lead_deg());
                    CHECK(*model.lead_deg() > 0.3);
                }
            });
        }
    }
}

TEST_CASE("orbit model: two unclamped targets are followed where a clamped one checks them") {
    SECTION("a client without look-ahead, the dish's limits, the held-out pass") {
        // With the dish's limits the client says nothing while the satellite climbs the first
        // threshold above the floor, then sends a target every 20 s: the third unclamped one came
        // 40 s after the first (docs/benchmarks.md). Two fix the orbit; the clamped target sent
        // below the floor checks it, and tells the gaps' lead of 2.5 deg from none. Measured when
        // written: trusted at the second (27 deg), lead none, at most 0.13 deg off until the third
        // (33 deg), 1.0 deg RMS over the 22 deg from the floor to 40.
        const TruePass pass = TruePass::load("heldout-iss-60");
        bool seen_second = false;
        feed_hinted(pass, 5.0, false, 2.5, [&](const OrbitModel& model, std::size_t unclamped) {
            if (unclamped != 2) {
                return;
            }
            INFO(model.describe());
            REQUIRE(model.trusted());
            REQUIRE(model.lead_deg());
            CHECK(*model.lead_deg() < 0.5);
            seen_second = true;
            Errors errors;
            for (double s = pass.rise(); s < pass.t.back(); s += 1.0) {
                const AzEl truth = pass.at(s);
                if (truth.el >= 27.0 && truth.el < 33.0 && pass.at(s + 1.0).el > truth.el) {
                    errors.add(sky_angle(model.predict(s)->position, truth));
                }
            }
            INFO("from the second target to the third: RMS " << errors.rms() << ", max " << errors.max);
            CHECK(errors.max < 0.6);
        });
        CHECK(seen_second);
    }
    SECTION("a jog from the floor that turns is not an orbit") {
        OrbitModelSettings settings;
        settings.latitude_deg = site_latitude;
        settings.el_floor = 18.0;
        settings.el_cap = 65.0;
        OrbitModel model(settings);
        model.add(0.0, {100.0, 18.0}, 0.0);
        model.add(20.0, {110.0, 25.0}, 0.0);
        model.add(40.0, {100.0, 32.0}, 0.0);
        INFO(model.describe());
        CHECK_FALSE(model.trusted());
    }
}

TEST_CASE("orbit model: the predictor follows two checked targets with the lead the second one teaches") {
    // The second unclamped target's gap is the first the dish shows (it waited on its floor before):
    // the orbit saw that target without a lead, could not trust a free one, and is judged again once
    // the gap has taught one. Measured when written: followed from the second target (27 deg).
    const TruePass pass = TruePass::load("heldout-iss-60");
    PredictorSettings settings;
    settings.orbit.latitude_deg = 40.0;  // bench/generate_heldout_pass.py
    TargetPredictor predictor(settings);
    predictor.set_dish_limits(18.0, 65.0);
    GpredictLikeClient client(pass, 5.0, 18.0, 65.0, false);
    AzEl dish{client.aos_az() + 40.0, 18.0};
    std::size_t unclamped = 0;
    for (double now = pass.rise() - 60.0; now < client.end() && unclamped < 2; now += 1.0) {
        if (const auto sent = client.tick(now, dish)) {
            predictor.observe(at(sent->arrival), sent->target, dish);
            dish = sent->target;
            unclamped += sent->target.el > 18.0 && sent->target.el < 65.0 ? 1 : 0;
        }
    }
    REQUIRE(unclamped == 2);
    INFO(predictor.describe());
    CHECK(predictor.pass_model_in_use());
}

TEST_CASE("orbit model: Gpredict's own lead is kept when two unclamped targets and a clamped one are put to it") {
    // Gpredict leads by its threshold: at its second unclamped target the clamped one must not take
    // that lead for none. Measured when written: trusted at the second on iss-45 and sso-45 (not on
    // the other two), the lead 5.0, and 0.2 / 0.5 deg at most off from the floor to 35 deg.
    for (const char* name : {"heldout-iss-60", "iss-45", "sso-45", "iss-85"}) {
        const TruePass pass = TruePass::load(name);
        feed_hinted(pass, 5.0, true, 5.0, [&](const OrbitModel& model, std::size_t unclamped) {
            if (unclamped == 2 && model.trusted()) {
                INFO(name << ": " << model.describe());
                REQUIRE(model.lead_deg());
                CHECK(*model.lead_deg() > 4.0);
                Errors errors;
                for (double s = pass.rise(); s < pass.t.back(); s += 1.0) {
                    const AzEl truth = pass.at(s);
                    if (truth.el >= 18.0 && truth.el < 35.0 && pass.at(s + 1.0).el > truth.el) {
                        errors.add(sky_angle(model.predict(s)->position, truth));
                    }
                }
                INFO("rising from the floor to 35 deg: RMS " << errors.rms() << ", max " << errors.max);
                CHECK(errors.max < 1.0);
            }
        });
    }
}

namespace {

// The predictor fed by the Gpredict-like client, the dish following the predictor (clamped to the
// G2's 18-65 deg) and read back by the client each second, every reading noted as `p` answered.
struct FollowedRun {
    std::optional<double> lead;          // the lead in use at the end of the pass
    double lowest_lead = 1e9;            // the lowest lead in use while there was one
    Errors followed;                     // the prediction against the truth, orbit in use, 20-60 deg
    int seconds_without_look_ahead = 0;  // the orbit in use, the client read as sending no look-ahead
    std::string description;
};

FollowedRun run_followed(const TruePass& pass, double latitude, double threshold, bool look_ahead,
                         bool note_every_reading, bool gaps = true) {
    PredictorSettings settings;
    settings.orbit.latitude_deg = latitude;
    TargetPredictor predictor(settings);
    predictor.set_dish_limits(18.0, 65.0);
    GpredictLikeClient client(pass, threshold, 18.0, 65.0, look_ahead);
    AzEl dish{client.aos_az(), 18.0};
    FollowedRun run;
    for (double now = pass.rise() - 60.0; now < client.end(); now += 1.0) {
        const AzEl read_back = dish;
        if (note_every_reading) {
            predictor.note_reported(at(now), read_back);
        }
        if (const auto sent = client.tick(now, read_back)) {
            predictor.observe(at(sent->arrival), sent->target, gaps ? std::optional<AzEl>(read_back) : std::nullopt);
        }
        if (const auto p = predictor.predict(at(now + 1.0))) {
            dish = {p->position.az, std::clamp(p->position.el, 18.0, 65.0)};
        }
        if (const auto lead = predictor.lead_threshold_deg()) {
            run.lowest_lead = std::min(run.lowest_lead, *lead);
        }
        if (predictor.pass_model_in_use() && predictor.client_without_look_ahead()) {
            ++run.seconds_without_look_ahead;
        }
        const AzEl truth = pass.at(now + 1.0);
        if (predictor.pass_model_in_use() && truth.el > 20.0 && truth.el < 60.0) {
            run.followed.add(sky_angle(predictor.predict(at(now + 1.0))->position, truth));
        }
    }
    run.lead = predictor.lead_threshold_deg();
    run.description = predictor.describe();
    return run;
}

}  // namespace

TEST_CASE("orbit model: a lead the targets fit is refuted by Gpredict's send rule, at 0.5 deg", "[figures]") {
    // A client without look-ahead whose gaps teach nothing (the held-out pass in the benchmark:
    // re-sends under 2 s apart are skipped) has its lead fitted with the orbit, and a few targets
    // fit a wrong lead with a wrong altitude: here 0.8-1.7 deg, and the dish trailed the satellite
    // by 1.0-1.5 deg. Gpredict sends only once the satellite is its threshold off the position
    // read back; this client sends whatever the dish does, and its targets arrive while the dish
    // read back holds the satellite well within the fitted lead. Measured when written: with every
    // `p` noted, none from 12 s after the orbit was trusted, the satellite 0.28 deg RMS off from 20 to
    // 60 deg (0.88 without); Gpredict's own lead kept (0.43).
    const TruePass pass = TruePass::load("heldout-iss-60");
    for (const bool look_ahead : {false, true}) {
        for (const bool noted : {false, true}) {
            // generate_heldout_pass.py: latitude 40
            const FollowedRun run = run_followed(pass, 40.0, 0.5, look_ahead, noted, false);
            std::printf("%s, every p %s: lead %.2f (lowest %.2f), followed %.3f RMS, max %.2f\n",
                        look_ahead ? "Gpredict" : "no look-ahead", noted ? "noted" : "not noted", run.lead.value_or(-1),
                        run.lowest_lead, run.followed.rms(), run.followed.max);
            INFO((look_ahead ? "Gpredict" : "no look-ahead")
                 << ", every p " << (noted ? "noted" : "not noted") << ": " << run.description);
            REQUIRE(run.lead);
            if (look_ahead) {
                CHECK(run.lowest_lead > 0.3);
            } else if (noted) {
                CHECK(*run.lead < 0.05);
                CHECK(run.followed.rms() < 0.4);
            }
        }
    }
}

TEST_CASE("orbit model: Gpredict's own lead survives its send rule on every bench pass, at 0.5 and 5 deg") {
    // The rule takes a lead for none only from targets Gpredict could not have sent: its own
    // targets, with the dish following the predictor and read back each second, never are, with
    // the lead learnt from the dish's gaps; at 5 deg also with it fitted with the orbit. (At 0.5 deg
    // a lead fitted without the gaps is lost on 5 of the 9 passes with or without the rule, which
    // there refutes a fitted 1.7 deg on sso-70, rightly, and takes none for it.)
    for (const char* name : pass_names) {
        const TruePass pass = TruePass::load(name);
        for (const double threshold : {0.5, 5.0}) {
            for (const bool gaps : {true, false}) {
                if (!gaps && threshold < 1.0) {
                    continue;
                }
                const FollowedRun run = run_followed(pass, site_latitude, threshold, true, true, gaps);
                INFO(name << " at " << threshold << " deg, gaps " << gaps << ": " << run.description);
                CHECK(run.lowest_lead > 0.5 * threshold);
                // The dish follows the predictor, so Gpredict sends only now and then and its steps
                // are far apart: still a client that leads (TargetPredictor::client_without_look_ahead()).
                if (gaps) {
                    CHECK(run.seconds_without_look_ahead == 0);
                }
            }
        }
    }
}
