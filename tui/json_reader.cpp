// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "json_reader.hpp"

#include <cctype>
#include <cstdlib>

namespace birdcage::tui {

const Json* Json::find(std::string_view key) const {
    for (const auto& [name, value] : members) {
        if (name == key) {
            return &value;
        }
    }
    return nullptr;
}

std::optional<double> Json::number_at(std::string_view key) const {
    const Json* value = find(key);
    if (value == nullptr || value->type != Type::number) {
        return std::nullopt;
    }
    return value->number;
}

std::string Json::text_at(std::string_view key, std::string fallback) const {
    const Json* value = find(key);
    return value != nullptr && value->type == Type::string ? value->text : fallback;
}

namespace {

class Reader {
public:
    explicit Reader(std::string_view text) : text_(text) {}

    bool value(Json& out, int depth) {
        if (depth > 64) {
            return fail("nested too deeply");
        }
        skip_space();
        if (at_end()) {
            return fail("a value was expected");
        }
        const char c = text_[pos_];
        if (c == '{') {
            return object(out, depth);
        }
        if (c == '[') {
            return array(out, depth);
        }
        if (c == '"') {
            out.type = Json::Type::string;
            return string(out.text);
        }
        if (literal("true")) {
            out.type = Json::Type::boolean;
            out.boolean = true;
            return true;
        }
        if (literal("false")) {
            out.type = Json::Type::boolean;
            return true;
        }
        if (literal("null")) {
            out.type = Json::Type::null;
            return true;
        }
        return number(out);
    }

    bool finish() {
        skip_space();
        return at_end() || fail("text after the value");
    }

    std::string why;

private:
    bool at_end() const { return pos_ >= text_.size(); }
    void skip_space() {
        while (!at_end() && std::isspace(static_cast<unsigned char>(text_[pos_]))) {
            ++pos_;
        }
    }
    bool fail(const char* what) {
        if (why.empty()) {
            why = std::string(what) + " at offset " + std::to_string(pos_);
        }
        return false;
    }
    bool literal(std::string_view word) {
        if (text_.substr(pos_, word.size()) == word) {
            pos_ += word.size();
            return true;
        }
        return false;
    }
    bool expect(char c) {
        skip_space();
        if (at_end() || text_[pos_] != c) {
            return fail(c == ':' ? "':' expected" : c == ',' ? "',' expected" : "a bracket expected");
        }
        ++pos_;
        return true;
    }

    bool object(Json& out, int depth) {
        out.type = Json::Type::object;
        ++pos_;
        skip_space();
        if (!at_end() && text_[pos_] == '}') {
            ++pos_;
            return true;
        }
        for (;;) {
            skip_space();
            std::string key;
            if (at_end() || text_[pos_] != '"' || !string(key) || !expect(':')) {
                return fail("a member name expected");
            }
            Json member;
            if (!value(member, depth + 1)) {
                return false;
            }
            out.members.emplace_back(std::move(key), std::move(member));
            skip_space();
            if (!at_end() && text_[pos_] == '}') {
                ++pos_;
                return true;
            }
            if (!expect(',')) {
                return false;
            }
        }
    }

    bool array(Json& out, int depth) {
        out.type = Json::Type::array;
        ++pos_;
        skip_space();
        if (!at_end() && text_[pos_] == ']') {
            ++pos_;
            return true;
        }
        for (;;) {
            Json item;
            if (!value(item, depth + 1)) {
                return false;
            }
            out.items.push_back(std::move(item));
            skip_space();
            if (!at_end() && text_[pos_] == ']') {
                ++pos_;
                return true;
            }
            if (!expect(',')) {
                return false;
            }
        }
    }

    static void append_utf8(std::string& out, unsigned code) {
        if (code < 0x80) {
            out += static_cast<char>(code);
        } else if (code < 0x800) {
            out += static_cast<char>(0xc0 | (code >> 6));
            out += static_cast<char>(0x80 | (code & 0x3f));
        } else {
            out += static_cast<char>(0xe0 | (code >> 12));
            out += static_cast<char>(0x80 | ((code >> 6) & 0x3f));
            out += static_cast<char>(0x80 | (code & 0x3f));
        }
    }

    bool string(std::string& out) {
        ++pos_;  // the opening quote
        while (!at_end()) {
            const char c = text_[pos_++];
            if (c == '"') {
                return true;
            }
            if (c != '\\') {
                out += c;
                continue;
            }
            if (at_end()) {
                break;
            }
            const char e = text_[pos_++];
            switch (e) {
                case 'n':
                    out += '\n';
                    break;
                case 't':
                    out += '\t';
                    break;
                case 'r':
                    out += '\r';
                    break;
                case 'b':
                    out += '\b';
                    break;
                case 'f':
                    out += '\f';
                    break;
                case 'u': {
                    if (pos_ + 4 > text_.size()) {
                        return fail("a short \\u escape");
                    }
                    const std::string hex(text_.substr(pos_, 4));
                    char* end = nullptr;
                    const unsigned long code = std::strtoul(hex.c_str(), &end, 16);
                    if (end != hex.c_str() + 4) {
                        return fail("a bad \\u escape");
                    }
                    pos_ += 4;
                    // A surrogate half stands for a character outside the BMP: shown as '?'.
                    append_utf8(out, code >= 0xd800 && code < 0xe000 ? '?' : static_cast<unsigned>(code));
                    break;
                }
                default:
                    out += e;  // \" \\ \/
            }
        }
        return fail("an unterminated string");
    }

    bool number(Json& out) {
        const std::size_t start = pos_;
        while (!at_end() && (std::isdigit(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '-' ||
                             text_[pos_] == '+' || text_[pos_] == '.' || text_[pos_] == 'e' || text_[pos_] == 'E')) {
            ++pos_;
        }
        const std::string digits(text_.substr(start, pos_ - start));
        char* end = nullptr;
        out.number = std::strtod(digits.c_str(), &end);
        if (digits.empty() || end != digits.c_str() + digits.size()) {
            pos_ = start;
            return fail("a value was expected");
        }
        out.type = Json::Type::number;
        return true;
    }

    std::string_view text_;
    std::size_t pos_ = 0;
};

}  // namespace

std::optional<Json> parse_json(std::string_view text, std::string* why) {
    Reader reader(text);
    Json out;
    if (reader.value(out, 0) && reader.finish()) {
        return out;
    }
    if (why != nullptr) {
        *why = reader.why;
    }
    return std::nullopt;
}

}  // namespace birdcage::tui
