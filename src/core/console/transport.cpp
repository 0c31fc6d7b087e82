// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "console/transport.hpp"

namespace birdcage {

Transport::~Transport() = default;

}  // namespace birdcage
