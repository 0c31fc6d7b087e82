// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Auto-detection. What `q` may do: it is the documented way out of a submenu everywhere, and
// terminates the G2's shell at its root (docs/firmware.md 6.5). So it is sent only where a submenu was
// positively recognised: a prompt confirmed on two consecutive pokes, the `?` reply ending on that
// same prompt, not the G2 root shape `TRK>`, and a listing that names no root command of any variant.
// One deliberate exception keeps the Trav'ler Pro recognisable: a listing positively recognised as
// the HAL 0.0.00 root (which a Pro's ODU console also shows) at a confirmed prompt, with no trace of
// the G2 beyond the shared `TRK>` shape (no G2 command in the listing or its descriptions, no G2
// boot line), gets one `q` to see whether it leads to the Pro's IDU console. It is no new risk: the
// HAL 0.0.00 initialisation itself starts with the clients' `q` at the root (docs/firmware.md 2, 3.6).
// Before any `q` the console must have stayed quiet: output arriving then voids what was recognised.
#include "console/detect.hpp"

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <utility>

#include "console/session.hpp"
#include "console/synchroniser.hpp"

namespace birdcage {
namespace {

using namespace std::chrono_literals;

constexpr auto help_timeout = 3000ms;
constexpr auto resync_budget = 5000ms;  // after a `q`: the console is up, only the menu changed
constexpr int max_levels = 4;           // deepest menu nesting seen: Pro IDU > ODU > mot
constexpr char force_hint[] =
    "force one with -C variant=<hal000|hal205|pro|carryout2003|g2> or use that variant's own model";

std::string trimmed(std::string_view text) {
    const auto first = text.find_first_not_of(' ');
    if (first == std::string_view::npos) {
        return {};
    }
    const auto last = text.find_last_not_of(' ');
    return std::string(text.substr(first, last - first + 1));
}

std::string variant_name(VariantId id) {
    return std::string(profile(id).short_name);
}

std::string summary(const std::vector<VariantScore>& ranking) {
    std::string text;
    for (const auto& entry : ranking) {
        if (entry.score == 0) {
            continue;
        }
        text += (text.empty() ? "" : "; ") + variant_name(entry.variant) + " " + std::to_string(entry.score);
        std::string reasons;
        for (const auto& reason : entry.reasons) {
            reasons += (reasons.empty() ? "" : ", ") + reason;
        }
        text += " (" + reasons + ")";
    }
    return text.empty() ? std::string("no evidence for any variant") : text;
}

std::string listing_text(const HelpListing& help) {
    std::string text;
    for (const auto& w : help.commands) {
        text += (text.empty() ? "" : " ") + w;
    }
    return text.empty() ? std::string("(nothing)") : text;
}

std::string answer_name(ProbeAnswer answer) {
    switch (answer) {
        case ProbeAnswer::any:
            return "anything";
        case ProbeAnswer::nothing:
            return "no position";
        case ProbeAnswer::travler_position:
            return "a Trav'ler position (AZ = ...)";
        case ProbeAnswer::g2_position:
            return "a G2 position (Angle[0] = ...)";
    }
    return "?";
}

ProbeAnswer expected_answer(const DetectionProbe& probe, VariantId id) {
    for (const auto& e : probe.expected) {
        if (e.variant == id) {
            return e.answer;
        }
    }
    return ProbeAnswer::any;
}

// The variants a probe can still tell apart: some of them expect different definite answers.
bool probe_discriminates(const DetectionProbe& probe, const std::vector<VariantId>& candidates) {
    std::set<ProbeAnswer> definite;
    bool some_any = false;
    for (VariantId id : candidates) {
        const ProbeAnswer a = expected_answer(probe, id);
        if (a == ProbeAnswer::any) {
            some_any = true;
        } else {
            definite.insert(a);
        }
    }
    return definite.size() > 1 || (definite.size() == 1 && some_any);
}

std::string names_of(const std::vector<VariantId>& ids) {
    std::string text;
    for (VariantId id : ids) {
        text += (text.empty() ? "" : ", ") + variant_name(id);
    }
    return text.empty() ? std::string("none") : text;
}

std::string first_line(const std::vector<std::string>& lines) {
    return lines.empty() ? std::string("nothing") : "\"" + escape_bytes(lines.front()) + "\"";
}

// What the evidence adds when the console may be `outer`'s inner console left open.
std::string inside_note(VariantId outer) {
    const FirmwareProfile& inside = profile(outer);
    return " (a " + std::string(inside.display_name) +
           " left inside its ODU console looks the same; elevation kept <= " +
           std::to_string(static_cast<int>(inside.el_max)) + ")";
}

// One probe step's outcome: `command`, then the position query; what came back.
struct Asked {
    ProbeAnswer answer = ProbeAnswer::nothing;
    std::vector<std::string> lines;
    std::string prompt;
};

// One detection over one console: reads the listing at each menu level, ranks the evidence, and
// where it does not decide, leaves submenus and probes with harmless commands (the rules at the top).
class Detector {
public:
    Detector(Transport& transport, const LogSink& log, std::chrono::milliseconds boot_timeout)
        : log_(log), session_(transport, probe_profile(), log), boot_timeout_(boot_timeout) {}

    Result<Detection> run();

private:
    Status read_help();
    Status leave_menu(const std::string& menu);
    Status back_to_root(std::string_view menu, ProbeAnswer answer, const std::string& prompt_seen,
                        const std::string& root_prompt);
    Result<Asked> ask(std::string_view command);
    Result<bool> leave_motor_menu();
    Result<std::optional<Detection>> probe(const std::vector<VariantScore>& scores);
    Result<Detection> conclude(const VariantScore& winner, const std::vector<VariantScore>& ranking);

    const LogSink& log_;
    ConsoleSession session_;
    std::chrono::milliseconds boot_timeout_;
    ConsoleEvidence evidence_;
    std::vector<std::string> help_lines_;  // the latest `?` listing (or the synchroniser's probe reply)
    bool reply_on_same_prompt_ = true;
    std::string probe_log_;  // each probe and its answer, for the evidence and the failure message
};

}  // namespace

// The console's `?` listing at the current prompt, and whether it ended on that same prompt.
Status Detector::read_help() {
    auto help = session_.transact("?", help_timeout);
    if (!help && help.status.code != Errc::timeout) {
        return help.status;
    }
    help_lines_ = help.value.lines;
    evidence_.lines.insert(evidence_.lines.end(), help.value.lines.begin(), help.value.lines.end());
    // The session keeps boot lines out of a reply; they are evidence all the same.
    if (!session_.last_boot_line().empty()) {
        evidence_.lines.push_back(session_.last_boot_line());
    }
    reply_on_same_prompt_ = trimmed(help.value.prompt) == evidence_.prompt;
    return Status::ok();
}

// `q`, then the console must come into sync again before anything is concluded. `menu` tells
// the hazard guard where the caller recognised the console to be. A G2-only command in the
// listing, or anywhere in the output, at the G2 root shape keeps the guard's own verdict
// (root: `q` refused), whatever the caller concluded.
Status Detector::leave_menu(const std::string& menu) {
    if (auto heard = session_.listen(probe_profile().quiet_gap);
        !heard.value.lines.empty() || !heard.value.prompt.empty()) {
        return Status{Errc::protocol,
                      "auto-detect: the console printed more (\"" +
                          escape_bytes(heard.value.lines.empty() ? heard.value.prompt : heard.value.lines.back()) +
                          "\") while its menu was being left; not sending q"};
    }
    if (!(is_g2_root_shape(evidence_.prompt) &&
          (names_a_g2_only_command(evidence_.help) || g2_command_heard(evidence_.lines)))) {
        session_.set_menu(menu);  // recognised by the caller (see the rules at the top)
    }
    if (auto q = session_.transact("q", help_timeout); !q && q.status.code != Errc::timeout) {
        return q.status;
    }
    auto again = session_.synchronise(console_sync_settings(probe_profile(), resync_budget));
    if (!again) {
        return again.status;
    }
    evidence_.lines.insert(evidence_.lines.end(), again.value.heard.begin(), again.value.heard.end());
    evidence_.prompt = again.value.prompt;
    help_lines_ = again.value.probe_reply;
    reply_on_same_prompt_ = true;
    return Status::ok();
}

// After a probe command: if the console now sits in a menu (a position answered, or a prompt
// other than the root's, confirmed on two pokes), leave it with `q` as every variant does
// (docs/firmware.md 2) -- never at the G2 root shape.
Status Detector::back_to_root(std::string_view menu, ProbeAnswer answer, const std::string& prompt_seen,
                              const std::string& root_prompt) {
    if (answer == ProbeAnswer::nothing && (prompt_seen.empty() || prompt_seen == root_prompt)) {
        return Status::ok();
    }
    auto here = session_.synchronise(console_sync_settings(probe_profile(), resync_budget));
    if (!here) {
        return here.status;
    }
    evidence_.lines.insert(evidence_.lines.end(), here.value.heard.begin(), here.value.heard.end());
    const std::string now = here.value.prompt;
    const bool in_menu = answer != ProbeAnswer::nothing || (!now.empty() && now != root_prompt);
    if (!in_menu || is_g2_root_shape(now)) {
        evidence_.prompt = now;
        return Status::ok();
    }
    evidence_.prompt = now;
    emit(log_, LogLevel::verbose,
         "auto-detect probe: leaving " + std::string(menu) + " (prompt \"" + now + "\") with q");
    return leave_menu(std::string(menu));
}

// One probe step: `command` (none: only the query), then the position query.
Result<Asked> Detector::ask(std::string_view command) {
    Asked asked;
    for (std::string_view step : {command, std::string_view("a")}) {
        if (step.empty()) {
            continue;
        }
        auto reply = session_.transact(step, help_timeout);
        if (!reply && reply.status.code != Errc::timeout && reply.status.code != Errc::protocol) {
            return {asked, reply.status};
        }
        asked.lines.insert(asked.lines.end(), reply.value.lines.begin(), reply.value.lines.end());
        asked.prompt = trimmed(reply.value.prompt);
    }
    asked.answer = position_answer(asked.lines);
    return {asked, Status::ok()};
}

// Already inside a motor menu whose listing names a root command (a title, say)? The position
// query answers there; the menu probes only mean something from the root, so the console is
// taken back to it first. True when it was in a motor menu (its listing is then read again).
Result<bool> Detector::leave_motor_menu() {
    auto here = ask("");
    if (!here) {
        return {false, here.status};
    }
    emit(log_, LogLevel::verbose,
         "auto-detect probe: \"a\" at " +
             (evidence_.prompt.empty() ? std::string("the prompt-less console") : evidence_.prompt) + " drew " +
             answer_name(here.value.answer) + " (" + first_line(here.value.lines) + ")");
    if (here.value.answer == ProbeAnswer::nothing) {
        return {false, Status::ok()};
    }
    if (Status back = back_to_root("motor menu", here.value.answer, here.value.prompt, evidence_.prompt); !back) {
        return {false, back};
    }
    return {true, Status::ok()};
}

// Where the evidence leaves more than one variant: the probes of detection_probes(), most
// telling first, each ruling out the variants whose documented answer differs.
Result<std::optional<Detection>> Detector::probe(const std::vector<VariantScore>& scores) {
    std::vector<VariantId> candidates;
    const int top = scores.empty() ? 0 : scores.front().score;
    for (const auto& entry : scores) {
        if (top < winning_score || entry.score > top - winning_margin) {
            candidates.push_back(entry.variant);
        }
    }
    std::map<VariantId, int> matched;  // definite expectations met, per candidate
    const std::string root_prompt = evidence_.prompt;
    emit(log_, LogLevel::verbose,
         "auto-detect: the evidence does not decide between " + names_of(candidates) +
             "; probing with commands that are harmless on every variant");
    for (const DetectionProbe& row : detection_probes()) {
        if (candidates.size() < 2) {
            break;
        }
        if (!probe_discriminates(row, candidates)) {
            continue;
        }
        auto asked = ask(row.enter);
        if (!asked) {
            return {std::nullopt, asked.status};
        }
        std::vector<VariantId> kept, ruled_out;
        for (VariantId id : candidates) {
            const ProbeAnswer expected = expected_answer(row, id);
            if (expected == ProbeAnswer::any || expected == asked.value.answer) {
                kept.push_back(id);
                matched[id] += expected == ProbeAnswer::any ? 0 : 1;
            } else {
                ruled_out.push_back(id);
            }
        }
        const std::string entry = "\"" + std::string(row.enter) + "\" then \"a\" drew " +
                                  answer_name(asked.value.answer) + " (" + first_line(asked.value.lines) + ")";
        probe_log_ += (probe_log_.empty() ? "" : "; ") + entry;
        emit(log_, LogLevel::verbose,
             "auto-detect probe: " + entry + "; rules out " + names_of(ruled_out) +
                 "; still possible: " + names_of(kept));
        candidates = std::move(kept);
        if (Status back = back_to_root(row.enter, asked.value.answer, asked.value.prompt, root_prompt); !back) {
            return {std::nullopt, back};
        }
    }
    // The candidate whose definite answers matched most, then the one with most evidence.
    auto score_of = [&](VariantId id) {
        const auto it =
            std::find_if(scores.begin(), scores.end(), [&](const VariantScore& e) { return e.variant == id; });
        return it == scores.end() ? 0 : it->score;
    };
    std::stable_sort(candidates.begin(), candidates.end(), [&](VariantId a, VariantId b) {
        return std::make_pair(matched[a], score_of(a)) > std::make_pair(matched[b], score_of(b));
    });
    if (candidates.empty() || (candidates.size() > 1 && matched[candidates[0]] == matched[candidates[1]] &&
                               score_of(candidates[0]) == score_of(candidates[1]))) {
        return {std::nullopt, Status::ok()};
    }
    Detection d;
    d.variant = candidates.front();
    d.evidence = "auto-detected by probing: " + probe_log_ + " -> " + std::string(profile(d.variant).display_name) +
                 "; scores before probing: " + summary(scores);
    if (const auto outer = profile(d.variant).also_shown_inside) {
        d.maybe_inside = *outer;
        d.evidence += inside_note(*outer);
    }
    emit(log_, LogLevel::verbose, d.evidence);
    return {d, Status::ok()};
}

// The evidence named a clear winner. Where that variant's root is also what another variant's
// inner console shows (a Pro left in its ODU console), one `q` tells them apart when it is safe.
Result<Detection> Detector::conclude(const VariantScore& winner, const std::vector<VariantScore>& ranking) {
    Detection d;
    d.variant = winner.variant;
    d.evidence = "auto-detected: " + summary({winner});
    // The `TRK>` shape alone is no trace: the HAL 0.0.00 init sends `q` at its root anyway.
    const bool no_trace_of_g2 = q_killer_score(ranking) <= (is_g2_root_shape(evidence_.prompt) ? 1 : 0);
    if (const auto outer = profile(winner.variant).also_shown_inside) {
        // The only `q` at a root, even one shaped like the G2's `TRK>`: allowed because the
        // listing positively shows a Trav'ler/ODU root (shows_travler_root), where `q` is
        // the upstream clients' harmless idiom (docs/firmware.md 2), and nothing else hints
        // at a G2. It tells a Pro left in its ODU console from a HAL 0.0.00.
        if (no_trace_of_g2 && shows_travler_root(evidence_.help) && !g2_command_heard(evidence_.lines) &&
            !session_.reboot_seen() && !g2_text_in(session_.recent_output()) && !evidence_.prompt.empty() &&
            reply_on_same_prompt_) {
            if (Status left = leave_menu("travler root"); !left) {
                return {{}, left};
            }
            if (Status read = read_help(); !read) {
                return {{}, read};
            }
            evidence_.help = parse_help_listing(help_lines_);
            const auto after = clear_winner(rank_evidence(evidence_));
            if (after && after->variant == *outer) {
                d.variant = *outer;
                d.evidence += "; q from there led to the IDU console (? lists odu): a " +
                              std::string(profile(*outer).display_name);
            } else {
                d.maybe_inside = *outer;
            }
        } else {
            d.maybe_inside = *outer;
        }
        if (d.maybe_inside) {
            d.evidence += inside_note(*outer);
        }
    }
    emit(log_, LogLevel::verbose, d.evidence);
    return {d, Status::ok()};
}

Result<Detection> Detector::run() {
    auto synced = session_.synchronise(console_sync_settings(probe_profile(), boot_timeout_));
    if (!synced) {
        return {{}, Status{synced.status.code, "auto-detect: " + synced.status.message + "; " + force_hint}};
    }
    evidence_.lines = synced.value.heard;
    evidence_.prompt = synced.value.prompt;
    help_lines_ = synced.value.probe_reply;
    reply_on_same_prompt_ = true;

    bool probed = false;
    bool asked_here = false;
    std::set<std::string> left_menus;  // prompt and listing of each menu left with `q`
    std::vector<VariantScore> ranking;
    for (int level = 0; level < max_levels; ++level) {
        if (help_lines_.empty()) {
            if (Status read = read_help(); !read) {
                return {{}, read};
            }
        }
        evidence_.help = parse_help_listing(help_lines_);
        ranking = rank_evidence(evidence_);
        emit(log_, LogLevel::verbose,
             "auto-detect: prompt \"" + evidence_.prompt + "\", ? lists " + listing_text(evidence_.help) +
                 "; scores: " + summary(ranking));
        if (const auto winner = clear_winner(ranking)) {
            return conclude(*winner, ranking);
        }
        // A `q` that led back to the same prompt and listing showed this is the root after all.
        const bool left_before = !left_menus.insert(evidence_.prompt + "\n" + listing_text(evidence_.help)).second;
        const bool submenu = !evidence_.prompt.empty() && reply_on_same_prompt_ &&
                             !is_g2_root_shape(evidence_.prompt) && !evidence_.help.commands.empty() &&
                             !names_a_root_command(evidence_.help) && !left_before;
        if (!submenu) {
            if (probed) {
                break;
            }
            if (!asked_here) {
                asked_here = true;
                auto left = leave_motor_menu();
                if (!left) {
                    return {{}, left.status};
                }
                if (left.value) {
                    help_lines_.clear();
                    continue;
                }
            }
            probed = true;
            auto found = probe(ranking);
            if (!found) {
                return {{},
                        Status{found.status.code,
                               "auto-detect: while probing: " + found.status.message + "; " + force_hint}};
            }
            if (found.value) {
                return {*found.value, Status::ok()};
            }
            break;
        }
        emit(log_, LogLevel::verbose,
             "auto-detect: " + evidence_.prompt + " is a submenu (its ? names no root command); leaving it with q");
        if (Status left = leave_menu("submenu"); !left) {
            return {{}, left};
        }
    }
    return {{},
            Status{Errc::protocol, "auto-detect: not sure which firmware this is (prompt \"" + evidence_.prompt +
                                       "\", ? lists " + listing_text(evidence_.help) + "; scores: " + summary(ranking) +
                                       ")" + (probe_log_.empty() ? std::string() : "; probes: " + probe_log_) + "; " +
                                       force_hint}};
}

Result<Detection> detect_variant(Transport& transport, const LogSink& log, std::chrono::milliseconds boot_timeout) {
    return Detector(transport, log, boot_timeout).run();
}

}  // namespace birdcage
