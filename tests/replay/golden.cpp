// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "golden.hpp"

#include <algorithm>
#include <optional>
#include <set>
#include <sstream>

#include "birdcage_sim/transcript.hpp"
#include "firmware/protocol.hpp"
#include "tracking/az_mapping.hpp"

namespace birdcage::golden {

namespace {

std::string degrees(double value) {
    return format_degrees(value);
}

std::string az_el(const AzEl& position) {
    return "az=" + degrees(position.az) + " el=" + degrees(position.el);
}

std::string mapping_fields(const azmap::Learner& learner) {
    std::string text;
    if (const auto stated = learner.stated()) {
        text = "az_mapping=stated:" + std::string(azmap::mapping_name(*stated));
    } else if (const auto known = learner.known()) {
        text = "az_mapping=learnt:" + std::string(azmap::mapping_name(*known));
    } else {
        text = "az_mapping=auto";
    }
    std::string possible;
    for (const auto mapping : azmap::all_mappings) {
        if (!learner.possible(mapping))
            continue;
        possible += (possible.empty() ? "" : ",") + std::string(azmap::mapping_name(mapping));
    }
    text += " possible=" + (possible.empty() ? std::string("none") : possible);
    text += " planning=" + std::string(azmap::mapping_name(learner.planning()));
    const auto wrap_point = learner.wrap_point();
    text += " wrap_point=" + (wrap_point ? degrees(*wrap_point) : std::string("unknown"));
    return text;
}

std::vector<std::string> split_lines(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream stream(text);
    for (std::string line; std::getline(stream, line);)
        lines.push_back(line);
    return lines;
}

bool is_annotation(const std::string& line) {
    return line.empty() || line.front() == '#';
}

}  // namespace

std::string status_field(const Status& status) {
    if (status)
        return "ok";
    return std::string("error=") + errc_name(status.code);
}

std::string quoted(std::string_view text) {
    return "\"" + sim::escape_chunk(text) + "\"";
}

const char* yes_no(bool value) {
    return value ? "yes" : "no";
}

std::vector<std::string> state_lines(const Controller& controller) {
    const auto& profile = controller.profile();
    std::vector<std::string> lines;
    std::string state = "state: variant=" + std::string(profile.short_name) +
                        " detected=" + yes_no(controller.auto_detected()) +
                        " baud=" + std::to_string(controller.line_baud());
    state += " menu=" +
             (controller.console_menu().empty() ? std::string("unknown") : golden::quoted(controller.console_menu()));
    state += " prompt=" +
             (controller.console_prompt().empty() ? std::string("none") : golden::quoted(controller.console_prompt()));
    state += std::string(" initialised=") + yes_no(controller.initialised()) +
             " homed=" + yes_no(!controller.unhomed()) + " tracker_enabled=" + yes_no(controller.tracker_enabled());
    lines.push_back(state);

    if (const auto position = controller.last_position()) {
        lines.push_back("  position: " + az_el(*position) +
                        " source=" + (controller.position_estimated() ? "commanded" : "readback"));
    } else {
        lines.emplace_back("  position: unknown");
    }
    const auto target = controller.current_target();
    lines.push_back("  target: " + (target ? az_el(*target) : std::string("none")));
    lines.push_back("  el_limits: min=" + degrees(controller.el_min()) + " max=" + degrees(controller.el_max()));
    lines.push_back(std::string("  pointing: leapfrog=") + (controller.leapfrog() ? "on" : "off"));

    const WrapTracker& wrap = controller.wrap_tracker();
    const auto mechanical = wrap.mechanical();
    const auto target_mechanical = wrap.target_mechanical();
    lines.push_back("  wrap: travel=" + degrees(wrap.window().min) + ".." + degrees(wrap.window().max) +
                    " mechanical_az=" + (mechanical ? degrees(*mechanical) : std::string("unknown")) +
                    " az_reported=" + (wrap.reports_mechanical() ? "mechanical" : "display") +
                    " target_mechanical_az=" + (target_mechanical ? degrees(*target_mechanical) : std::string("none")) +
                    " " + mapping_fields(wrap.learner()));
    return lines;
}

std::string event_line(const ConsoleEvent& event) {
    if (event.kind == ConsoleEvent::Kind::reached) {
        return "reached: menu=" + (event.menu.empty() ? std::string("unknown") : golden::quoted(event.menu)) +
               " prompt=" + (event.text.empty() ? std::string("none") : golden::quoted(event.text));
    }
    std::string line = "parsed: " + std::string(console_event_name(event.kind));
    if (!event.command.empty())
        line += " command=" + golden::quoted(event.command);
    if (event.position)
        line += " " + az_el(*event.position);
    if (event.angle)
        line += " angle=" + degrees(*event.angle);
    switch (event.kind) {
        case ConsoleEvent::Kind::fault:
        case ConsoleEvent::Kind::unrecognised:
            line += " line=" + (event.text.empty() ? std::string("none") : golden::quoted(event.text));
            break;
        default:
            break;
    }
    return line;
}

std::vector<std::string> content_lines(const std::string& text) {
    std::vector<std::string> lines;
    for (auto& line : split_lines(text)) {
        if (!is_annotation(line))
            lines.push_back(std::move(line));
    }
    return lines;
}

std::string keep_annotations(const std::string& previous, const std::string& fresh, std::vector<std::string>& dropped) {
    const auto fresh_lines = split_lines(fresh);
    const std::set<std::string> generated(fresh_lines.begin(),
                                          std::find_if(fresh_lines.begin(), fresh_lines.end(),
                                                       [](const std::string& line) { return !is_annotation(line); }));
    struct Note {
        std::vector<std::string> lines;
        std::optional<std::string> before;  // the content line it preceded; nullopt: the end
    };
    std::vector<Note> notes;
    std::vector<std::string> pending;
    for (const auto& line : split_lines(previous)) {
        if (is_annotation(line)) {
            if (!generated.count(line))
                pending.push_back(line);
            continue;
        }
        if (!pending.empty())
            notes.push_back({std::exchange(pending, {}), line});
    }
    if (!pending.empty())
        notes.push_back({pending, std::nullopt});

    // Each note goes before the first matching line after the previous note's, in order.
    std::vector<std::vector<std::string>> before(fresh_lines.size() + 1);
    std::size_t cursor = 0;
    for (auto& note : notes) {
        std::size_t at = fresh_lines.size();
        if (note.before) {
            const auto found =
                std::find(fresh_lines.begin() + static_cast<std::ptrdiff_t>(cursor), fresh_lines.end(), *note.before);
            if (found == fresh_lines.end()) {
                dropped.insert(dropped.end(), note.lines.begin(), note.lines.end());
                continue;
            }
            at = static_cast<std::size_t>(found - fresh_lines.begin());
            cursor = at + 1;
        }
        before[at].insert(before[at].end(), note.lines.begin(), note.lines.end());
    }
    std::string merged;
    for (std::size_t i = 0; i <= fresh_lines.size(); ++i) {
        for (const auto& line : before[i])
            merged += line + '\n';
        if (i < fresh_lines.size())
            merged += fresh_lines[i] + '\n';
    }
    return merged;
}

}  // namespace birdcage::golden
