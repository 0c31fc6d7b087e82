// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "hamlib_abi.hpp"

#include <cctype>
#include <charconv>

namespace birdcage::hamlib {
namespace {

bool digit(char c) {
    return std::isdigit(static_cast<unsigned char>(c)) != 0;
}

// The number at text[pos...], advancing pos past it.
std::optional<int> number_at(std::string_view text, std::size_t& pos) {
    int value = 0;
    const auto [end, error] = std::from_chars(text.data() + pos, text.data() + text.size(), value);
    if (error != std::errc{})
        return std::nullopt;
    pos = static_cast<std::size_t>(end - text.data());
    return value;
}

std::string describe(std::string_view version, int soname) {
    std::string text = "Hamlib " + std::string(version.empty() ? "(unknown version)" : version);
    if (soname > 0)
        text += " (libhamlib.so." + std::to_string(soname) + ")";
    return text;
}

}  // namespace

std::optional<Version> parse_version(std::string_view text) {
    for (std::size_t start = 0; start < text.size(); ++start) {
        if (!digit(text[start]) || (start > 0 && (digit(text[start - 1]) || text[start - 1] == '.')))
            continue;
        std::size_t pos = start;
        Version version;
        const auto major = number_at(text, pos);
        if (!major || pos >= text.size() || text[pos] != '.' || pos + 1 >= text.size() || !digit(text[pos + 1]))
            continue;
        ++pos;
        const auto minor = number_at(text, pos);
        if (!minor)
            continue;
        version.major = *major;
        version.minor = *minor;
        if (pos + 1 < text.size() && text[pos] == '.' && digit(text[pos + 1])) {
            ++pos;
            version.patch = number_at(text, pos).value_or(0);
        }
        return version;
    }
    return std::nullopt;
}

std::optional<int> soname_major(std::string_view path) {
    const std::size_t so = path.find(".so.");
    if (so == std::string_view::npos)
        return std::nullopt;
    std::size_t pos = so + 4;
    if (pos >= path.size() || !digit(path[pos]))
        return std::nullopt;
    return number_at(path, pos);
}

AbiVerdict check_abi(std::string_view built_version, int built_soname, std::string_view running_version,
                     int running_soname) {
    // Only the release itself, not the build date and hash hamlib_version2 appends.
    const auto built = parse_version(built_version);
    const auto running = parse_version(running_version);
    auto release = [](std::string_view text, const std::optional<Version>& parsed) {
        if (!parsed)
            return std::string(text);
        return std::to_string(parsed->major) + "." + std::to_string(parsed->minor) + "." +
               std::to_string(parsed->patch);
    };
    const std::string both = "built for " + describe(release(built_version, built), built_soname) + ", running " +
                             describe(release(running_version, running), running_soname);
    auto refuse = [&](const std::string& why) { return AbiVerdict{false, both + ": " + why}; };

    if (built_soname > 0 && running_soname > 0 && built_soname != running_soname)
        return refuse("a different Hamlib ABI (struct s_rot differs)");
    if (!built || !running) {
        // Without both versions only an equal, known soname vouches for the layout.
        if (built_soname > 0 && built_soname == running_soname)
            return {true, both + ": version unreadable, same ABI by soname"};
        return refuse("cannot tell the running Hamlib's ABI");
    }
    if (built->major != running->major)
        return refuse("a different Hamlib major version");
    if (running->minor < built->minor)
        return refuse("an older Hamlib than the build's (it lacks API the build uses)");
    if (running->minor != built->minor || running->patch != built->patch)
        return {true, both + ": same ABI, accepted"};
    return {true, {}};
}

}  // namespace birdcage::hamlib
