// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "console/transport.hpp"

#include <filesystem>
#include <system_error>

namespace birdcage {

Transport::~Transport() = default;

bool is_pseudo_terminal(const std::string& path) {
    std::error_code error;
    const auto resolved = std::filesystem::canonical(path, error);
    return (error ? path : resolved.string()).rfind("/dev/pts/", 0) == 0;
}

}  // namespace birdcage
