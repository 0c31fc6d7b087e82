// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// A satellite pass as the benchmark uses it: azimuth/elevation samples over time, read from the
// CSV files bench/generate_passes.py writes (SGP4, synthetic elements; see docs/benchmarks.md).
#pragma once

#include <string>
#include <vector>

namespace bench {

struct Direction {
    double az = 0.0;  // degrees, [0, 360)
    double el = 0.0;  // degrees
};

class Pass {
public:
    // Throws std::runtime_error when the file is missing or malformed.
    static Pass load(const std::string& path);

    const std::string& name() const { return name_; }
    bool crosses_north() const { return crosses_north_; }
    double peak_el() const { return peak_el_; }
    double aos() const { return aos_; }  // seconds on the pass clock
    double los() const { return los_; }
    double tca() const { return tca_; }
    double aos_az() const { return aos_az_; }
    double los_az() const { return los_az_; }
    double site_latitude() const { return site_latitude_; }  // degrees north, from the header
    double first_time() const { return t_.front(); }
    double last_time() const { return t_.back(); }

    // Linear interpolation between samples (azimuth across north taken the short way). Outside the
    // sampled span the satellite is reported below the horizon, which is what it is there.
    Direction at(double t) const;
    // First time at or after `from` with elevation >= el, and last time with elevation >= el.
    double first_time_above(double el) const;
    double last_time_above(double el) const;

private:
    std::string name_;
    bool crosses_north_ = false;
    double site_latitude_ = 0.0;
    double peak_el_ = 0.0, aos_ = 0.0, los_ = 0.0, tca_ = 0.0, aos_az_ = 0.0, los_az_ = 0.0;
    std::vector<double> t_, az_, el_;
};

// Great-circle angle (degrees) between two directions.
double angle_between(Direction a, Direction b);
// a - b folded into (-180, 180].
double az_difference(double a, double b);

}  // namespace bench
