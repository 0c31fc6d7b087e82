// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The command-line convention every installed birdcage program shares (tests/cli checks it):
// `--flag=VALUE` or `--flag VALUE`. One cursor walks argv so the programs differ only in their
// flags, not in how a value is found.
#pragma once

#include <optional>
#include <string>

namespace birdcage::cli {

class ArgCursor {
public:
    ArgCursor(int argc, char** argv) : argc_(argc), argv_(argv) {}

    // Moves to the next argument; false when none is left. flag() is then the argument, or the
    // part before '=' of a `--flag=VALUE`.
    bool next() {
        if (++index_ >= argc_)
            return false;
        flag_ = argv_[index_];
        inline_value_.reset();
        if (const auto equals = flag_.find('='); flag_.starts_with("--") && equals != std::string::npos) {
            inline_value_ = flag_.substr(equals + 1);
            flag_.resize(equals);
        }
        return true;
    }

    const std::string& flag() const { return flag_; }
    int position() const { return index_; }  // 1 for the first argument
    // The flag came as `--flag=VALUE`: an error for a switch that takes none.
    bool has_inline_value() const { return inline_value_.has_value(); }
    // The flag's value: the part after '=', else the next argument (consumed); none at the end.
    std::optional<std::string> value() {
        if (inline_value_)
            return inline_value_;
        if (index_ + 1 >= argc_)
            return std::nullopt;
        return std::string(argv_[++index_]);
    }

private:
    int argc_;
    char** argv_;
    int index_ = 0;
    std::string flag_;
    std::optional<std::string> inline_value_;
};

}  // namespace birdcage::cli
