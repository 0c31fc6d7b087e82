// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "pass.hpp"

#include "harness.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace bench {

namespace {

// Reads `key value` pairs from the generator's "# peak_el ... crosses_north ..." header line.
double header_value(const std::string& line, const std::string& key) {
    const std::size_t at = line.find(" " + key + " ");
    if (at == std::string::npos) {
        throw std::runtime_error("pass header lacks " + key);
    }
    return std::stod(line.substr(at + key.size() + 2));
}

}  // namespace

double az_difference(double a, double b) {
    double d = std::fmod(a - b, 360.0);
    if (d <= -180.0) {
        d += 360.0;
    } else if (d > 180.0) {
        d -= 360.0;
    }
    return d;
}

double angle_between(Direction a, Direction b) {
    return e2e::sky_angle(a.az, a.el, b.az, b.el);
}

Pass Pass::load(const std::string& path) {
    std::ifstream in(path);
    if (!in) {
        throw std::runtime_error("cannot open pass file " + path);
    }
    Pass pass;
    const std::size_t slash = path.find_last_of('/');
    pass.name_ = path.substr(slash == std::string::npos ? 0 : slash + 1);
    pass.name_ = pass.name_.substr(0, pass.name_.rfind(".csv"));
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("# site lat", 0) == 0) {
            pass.site_latitude_ = header_value(line + " ", "lat");
            continue;
        }
        if (line.rfind("# peak_el", 0) == 0) {
            const std::string padded = line + " ";
            pass.peak_el_ = header_value(padded, "peak_el");
            pass.tca_ = header_value(padded, "tca_s");
            pass.aos_ = header_value(padded, "aos_s");
            pass.los_ = header_value(padded, "los_s");
            pass.aos_az_ = header_value(padded, "aos_az");
            pass.los_az_ = header_value(padded, "los_az");
            pass.crosses_north_ = header_value(padded, "crosses_north") != 0.0;
            continue;
        }
        if (line.empty() || line[0] == '#' || line[0] == 't') {
            continue;
        }
        std::istringstream fields(line);
        double t = 0, az = 0, el = 0;
        char comma1 = 0, comma2 = 0;
        if (!(fields >> t >> comma1 >> az >> comma2 >> el) || comma1 != ',' || comma2 != ',') {
            throw std::runtime_error("bad sample line in " + path + ": " + line);
        }
        pass.t_.push_back(t);
        pass.az_.push_back(az);
        pass.el_.push_back(el);
    }
    if (pass.t_.size() < 2 || pass.los_ <= pass.aos_) {
        throw std::runtime_error("pass file " + path + " has no usable samples or header");
    }
    return pass;
}

Direction Pass::at(double t) const {
    if (t < t_.front() || t > t_.back()) {
        return {aos_az_, -1.0};
    }
    const auto upper = std::upper_bound(t_.begin(), t_.end(), t);
    const std::size_t i = upper == t_.end() ? t_.size() - 1 : static_cast<std::size_t>(upper - t_.begin());
    const std::size_t j = i == 0 ? 0 : i - 1;
    const double span = t_[i] - t_[j];
    const double f = span > 0.0 ? (t - t_[j]) / span : 0.0;
    double az = az_[j] + f * az_difference(az_[i], az_[j]);
    az = std::fmod(az + 360.0, 360.0);
    return {az, el_[j] + f * (el_[i] - el_[j])};
}

double Pass::first_time_above(double el) const {
    for (std::size_t i = 0; i < t_.size(); ++i) {
        if (el_[i] >= el) {
            return t_[i];
        }
    }
    return t_.back();
}

double Pass::last_time_above(double el) const {
    for (std::size_t i = t_.size(); i-- > 0;) {
        if (el_[i] >= el) {
            return t_[i];
        }
    }
    return t_.front();
}

}  // namespace bench
