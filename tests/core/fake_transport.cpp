// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "fake_transport.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace birdcage::test {

Status FakeTransport::write(std::string_view bytes, Deadline) {
    if (hung_up_) {
        return Status{Errc::disconnected, "fake: hung up"};
    }
    written_ += bytes;
    for (char c : bytes) {
        if (c == '\r' || c == '\n') {
            commands_.push_back(line_);
            if (responder_) {
                for (auto& chunk : responder_(line_)) {
                    input_.push_back(std::move(chunk));
                }
            }
            line_.clear();
        } else {
            line_ += c;
        }
    }
    return Status::ok();
}

Result<std::size_t> FakeTransport::read(char* buf, std::size_t n, Deadline) {
    if (input_.empty() && !delayed_.empty() && delayed_.front().first <= 0) {
        input_.push_back(std::move(delayed_.front().second));
        delayed_.pop_front();
    }
    if (input_.empty()) {
        if (!delayed_.empty()) {
            --delayed_.front().first;
        }
        if (hung_up_) {
            return {0, Status{Errc::disconnected, "fake: hung up"}};
        }
        ++empty_reads_;
        return {0, Status{Errc::timeout, "fake: nothing queued"}};
    }
    std::string& chunk = input_.front();
    const std::size_t count = std::min(n, chunk.size());
    std::copy_n(chunk.data(), count, buf);
    chunk.erase(0, count);
    if (chunk.empty()) {
        input_.pop_front();
    }
    return {count, Status::ok()};
}

namespace {

std::string two_decimals(double value) {
    char text[64];
    std::snprintf(text, sizeof text, "%.2f", value);
    return text;
}

double approach(double from, double to, double step) {
    if (std::fabs(to - from) <= step) {
        return to;
    }
    return from + (to > from ? step : -step);
}

std::vector<std::string> split(const std::string& command) {
    std::istringstream in(command);
    std::vector<std::string> words;
    for (std::string word; in >> word;) {
        words.push_back(word);
    }
    return words;
}

}  // namespace

std::vector<std::string> FakeG2::respond(const std::string& command) {
    if (shell_killed) {
        return {};
    }
    std::string out = command + "\r\n";
    const auto words = split(command);
    if (words.empty()) {
        // bare CR reprints the prompt
    } else if (menu == "TRK" && words[0] == "q") {
        shell_killed = true;
        return {out + "Terminating shell\r\n"};
    } else if (words[0] == "q") {
        menu = "TRK";
    } else if (menu == "TRK" && words[0] == "mot") {
        menu = "MOT";
    } else if (menu == "TRK" && words[0] == "dvb" && lnb_polarity) {
        menu = "DVB";
    } else if (menu == "DVB" && words[0] == "dis") {
        // The rows of the real console's listing around the LNB's (firmware 02.02.48).
        out +=
            "Num  Parameter            Current                  Default\r\n"
            "4    Blind Scan Mode      ___trb_dvb_dss_____      ___trb_dvb_dss_____\r\n"
            "5    LNB Polarity         " +
            *lnb_polarity +
            "                  ---\r\n"
            "6    LNB Tone (ODU)       off                      off\r\n";
    } else if (menu == "DVB" && words[0] == "lnbdc" && words.size() == 2) {
        lnb_polarity = words[1] == "odu" ? "ODU:13V" : "ODU:18V";
    } else if (menu == "MOT" && words[0] == "a" && words.size() == 1) {
        az = approach(az, target_az, step_per_query);
        el = approach(el, target_el, step_per_query);
        if (homed) {
            out += "Angle[0] = " + two_decimals(az) + "\r\nAngle[1] = " + two_decimals(el) + "\r\n";
        } else {
            out += "Angle[0] = 2147483647.00\r\nAngle[1] = 2147483647.00\r\n";
        }
        for (const auto& line : extra_lines_after_query) {
            out += line + "\r\n";
        }
        extra_lines_after_query.clear();
    } else if (menu == "MOT" && words[0] == "a" && words.size() == 3) {
        const double value = std::stod(words[2]);
        (words[1] == "0" ? target_az : target_el) = value;
        out += "Angle = " + two_decimals(value) + "\r\n";
    }
    return {out, menu + ">"};
}

std::vector<std::string> FakeTravler::respond(const std::string& command) {
    std::string out = echo ? command + "\r\n" : std::string();
    const auto words = split(command);
    if (!words.empty() && words[0] == "?") {
        out += "a - show position\r\na <id> <deg> - move one motor\r\ng <az> <el> <sk> - go\r\nq - quit menu\r\n";
    } else if (!words.empty() && words[0] == "a" && words.size() == 1) {
        for (int axis = 0; axis < 2; ++axis) {
            double& value = axis == 0 ? az : el;
            if (queries_until_start[axis] > 0) {
                --queries_until_start[axis];
            } else {
                value = approach(value, axis == 0 ? target_az : target_el, step_per_query);
            }
        }
        out += "AZ = " + two_decimals(az) + "\r\nEL = " + two_decimals(el) + "\r\nSK = 0.00\r\n";
    } else if (!words.empty() && words[0] == "a" && words.size() == 3) {
        const double value = std::stod(words[2]);
        const int axis = words[1] == "0" ? 0 : 1;
        if ((axis == 0 ? az == target_az : el == target_el) && value != (axis == 0 ? az : el)) {
            queries_until_start[axis] = startup_queries;
        }
        (axis == 0 ? target_az : target_el) = value;
    }
    if (out.empty()) {
        return {};
    }
    return {out};
}

}  // namespace birdcage::test
