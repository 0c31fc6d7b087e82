// Firmware auto-detection at open: identifies the variant from what the console prints (prompt,
// boot lines, `?` help), never sending a documented hazard (no `q` unless the console is known to
// be inside a submenu; no moves, no NVS access).
#pragma once

#include <chrono>
#include <string>

#include "birdcage/errors.hpp"
#include "birdcage/log.hpp"
#include "birdcage/transport.hpp"
#include "birdcage/variants.hpp"

namespace birdcage {

struct Detection {
    VariantId variant{};
    std::string evidence;        // what identified it, for get_info and the debug log
    // The console looked like a Trav'ler HAL 0.0.00 root, which a Trav'ler Pro left inside its
    // ODU console also looks like: the caller should keep elevation under the Pro's 75 deg cap.
    bool maybe_pro_odu = false;
};

Result<Detection> detect_variant(Transport& transport, const LogSink& log, std::chrono::milliseconds boot_timeout);

}  // namespace birdcage
