// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Non-volatile settings as the `nvs` submenu shows them (docs/firmware.md §6.3, Appendix A).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace birdcage::sim {

struct NvsEntry {
    enum class Kind { boolean, integer, signed_integer, hex, real, real_mph };
    int index;
    std::string name;
    Kind kind;
    double current;
    double saved;
    double default_value;
};

class NvsTable {
public:
    NvsTable() = default;
    explicit NvsTable(std::vector<NvsEntry> entries) : entries_(std::move(entries)) {}

    NvsEntry* find(int index);
    const NvsEntry* find(int index) const;
    const NvsEntry* next_after(int index) const;
    const std::vector<NvsEntry>& entries() const { return entries_; }

    void load_saved();  // what a boot does: current = saved
    void save_all();    // `s`: saved = current

    static std::string format_value(const NvsEntry& entry, double value);
    static std::optional<double> parse_value(const NvsEntry& entry, std::string_view text);
    // Davidson's verbatim `d 20` (§6.3): header, dashed rule, and rows of this shape.
    static std::string header();
    static std::string rule();
    static std::string row(const NvsEntry& entry);
    // `e <idx> <v>` reply: old value, a dot, new pending value (§6.3).
    static std::string edit_row(const NvsEntry& entry, double old_value);

private:
    std::vector<NvsEntry> entries_;
};

std::vector<NvsEntry> g2_nvs_table();
std::vector<NvsEntry> travler_nvs_table();
std::vector<NvsEntry> travler_pro_nvs_table();
std::vector<NvsEntry> carryout2003_nvs_table();

}  // namespace birdcage::sim
