// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// What the core learnt from the dish's console, one event per piece of knowledge, as values: the
// places that turn a reply into knowledge (the position reader, the session's framer events and
// prompts, the G2 move acknowledgement) report it here as well as acting on it. Machines read
// these (the transcript golden files, docs/transcripts.md); the log keeps the prose. Boot output
// is not an event: it is the absence of knowledge until the console is synchronised again.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "base/azel.hpp"

namespace birdcage {

struct ConsoleEvent {
    enum class Kind {
        position,       // a position reply: `position` (display degrees, az in [0, 360))
        live_position,  // one live line of a running `g` (2003 Carryout, docs/firmware.md 8.4): `position`
        move_ack,       // the G2's `Angle = <f>` after `a <id> <deg>`: `command`, `angle`
        fault,          // a motor fault line (`AZ MOTOR STALLED`, docs/firmware.md 6.3): `text`, the dish's line
        unhomed,        // a reply to `command` carried the INT_MAX sentinel of an unhomed axis
        unrecognised,   // the reply to `command` was not what its parser needs: `text`, its first line (may be empty)
        reached,        // the console's menu or prompt changed: `menu` (empty: unknown), `text` the prompt
                        // (empty where the firmware's prompts are unknown and the menu was inferred)
    };
    Kind kind = Kind::position;
    std::optional<AzEl> position;
    std::optional<double> angle;
    std::string command;
    std::string text;
    std::string menu;

    static ConsoleEvent read_position(Kind kind, AzEl position) {
        ConsoleEvent event;
        event.kind = kind;
        event.position = position;
        return event;
    }
    static ConsoleEvent move_acknowledged(std::string command, double angle) {
        ConsoleEvent event;
        event.kind = Kind::move_ack;
        event.command = std::move(command);
        event.angle = angle;
        return event;
    }
    static ConsoleEvent fault_line(std::string line) {
        ConsoleEvent event;
        event.kind = Kind::fault;
        event.text = std::move(line);
        return event;
    }
    // unhomed, unrecognised
    static ConsoleEvent reply_to(Kind kind, std::string command, std::string first_line = {}) {
        ConsoleEvent event;
        event.kind = kind;
        event.command = std::move(command);
        event.text = std::move(first_line);
        return event;
    }
    static ConsoleEvent menu_reached(std::string menu, std::string prompt) {
        ConsoleEvent event;
        event.kind = Kind::reached;
        event.menu = std::move(menu);
        event.text = std::move(prompt);
        return event;
    }
};

// Called on the controller's thread, in the order the console's output was read.
using ConsoleEventSink = std::function<void(const ConsoleEvent&)>;

// The kind's enumerator name ("live_position"): stable, for output that machines compare.
constexpr std::string_view console_event_name(ConsoleEvent::Kind kind) {
    switch (kind) {
        case ConsoleEvent::Kind::position:
            return "position";
        case ConsoleEvent::Kind::live_position:
            return "live_position";
        case ConsoleEvent::Kind::move_ack:
            return "move_ack";
        case ConsoleEvent::Kind::fault:
            return "fault";
        case ConsoleEvent::Kind::unhomed:
            return "unhomed";
        case ConsoleEvent::Kind::unrecognised:
            return "unrecognised";
        case ConsoleEvent::Kind::reached:
            return "reached";
    }
    return "unknown";
}

}  // namespace birdcage
