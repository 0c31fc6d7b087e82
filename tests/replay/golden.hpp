// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The golden-file vocabulary of birdcage-regress (docs/transcripts.md, "Golden files"): every line
// is an event with stable keys, built from values (Errc names, the controller's accessors, wire
// bytes), never from the words of a Status message or Controller::describe(), so rewording a log
// line cannot break a transcript test.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "base/errors.hpp"
#include "console/console_events.hpp"
#include "dish/controller.hpp"

namespace birdcage::golden {

// "ok", or "error=<errc name>" (the message is left out on purpose).
std::string status_field(const Status& status);
// Dish text in double quotes, with the transcript escapes (`\r`, `\x20` at either end, ...).
// Call it qualified: on a std::string argument, ADL would find std::quoted, which escapes differently.
std::string quoted(std::string_view text);
// "yes" / "no".
const char* yes_no(bool value);
// The controller's state: a `state:` line and indented `position:`, `target:`, `el_limits:`,
// `pointing:` and `wrap:` lines, each key=value.
std::vector<std::string> state_lines(const Controller& controller);

// What the core learnt from a reply (console_events.hpp), one line: `parsed: <kind> key=value...`,
// or `reached: menu=... prompt=...` for a menu or prompt change.
std::string event_line(const ConsoleEvent& event);

// Lines the comparison looks at: not `#` comments, not blank.
std::vector<std::string> content_lines(const std::string& text);
// `fresh` with the hand-written `#` annotations (and blank lines) of `previous` put back before
// the line each preceded; an annotation whose line is gone is returned in `dropped`. Comment
// lines `fresh` generates itself are not copied twice.
std::string keep_annotations(const std::string& previous, const std::string& fresh, std::vector<std::string>& dropped);

}  // namespace birdcage::golden
