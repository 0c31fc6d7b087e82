// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Logging callback. Levels mirror Hamlib's err/warn/verbose/trace; the glue forwards to rot_debug.
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace birdcage {

enum class LogLevel { error, warning, verbose, trace };

using LogSink = std::function<void(LogLevel, const std::string&)>;

const char* to_string(LogLevel level);

// Printable form of wire bytes: \r, \n, \t, \\ and \xNN for everything outside printable ASCII.
std::string escape_bytes(std::string_view bytes);

// Calls the sink if there is one (a default-constructed LogSink is allowed and means "silent").
void emit(const LogSink& sink, LogLevel level, const std::string& message);

}  // namespace birdcage
