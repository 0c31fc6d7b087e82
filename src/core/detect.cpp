#include "birdcage/detect.hpp"

#include <algorithm>
#include <vector>

#include "birdcage/framer.hpp"
#include "birdcage/session.hpp"

namespace birdcage {
namespace {

using namespace std::chrono_literals;

constexpr auto help_timeout = 3000ms;
constexpr auto probe_timeout = 500ms;
constexpr auto progress_interval = 10000ms;
constexpr int max_levels = 4;  // deepest menu nesting seen: Pro IDU > ODU > mot

// The command words of a `?` listing: `Enter <word> - text` (6.3); otherwise each line's first word.
std::vector<std::string> help_words(const std::vector<std::string>& lines) {
    std::vector<std::string> words;
    for (const std::string& line : lines) {
        const auto open = line.find('<');
        const auto close = line.find('>', open == std::string::npos ? 0 : open);
        if (line.rfind("Enter <", 0) == 0 && close != std::string::npos) {
            words.push_back(line.substr(open + 1, close - open - 1));
            continue;
        }
        const auto start = line.find_first_not_of(" \t");
        if (start == std::string::npos) {
            continue;
        }
        const auto end = line.find_first_of(" \t", start);
        words.push_back(line.substr(start, end == std::string::npos ? std::string::npos : end - start));
    }
    return words;
}

std::string listed(const std::vector<std::string>& words) {
    std::string text;
    for (const auto& w : words) {
        text += (text.empty() ? "" : " ") + w;
    }
    return text;
}

}  // namespace

Result<Detection> detect_variant(Transport& transport, const LogSink& log, std::chrono::milliseconds boot_timeout) {
    ConsoleSession session(transport, probe_profile(), log);

    // 1. A live console: a prompt after a bare line ending, or any reply to `?`. A booting dish
    //    ignores input; keep probing until boot_timeout, showing progress.
    const auto started = Clock::now();
    std::chrono::milliseconds spent{0};
    auto elapsed = [&] {
        return std::max(spent, std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - started));
    };
    auto next_progress = progress_interval;
    Result<Reply> help;
    for (bool first = true;; first = false) {
        const Status synced = session.resync(probe_timeout);
        if (!synced && synced.code != Errc::timeout) {
            return {{}, synced};
        }
        help = session.transact("?", help_timeout);
        spent += probe_timeout;
        if (!help && help.status.code != Errc::timeout) {
            return {{}, help.status};
        }
        if (!help.value.lines.empty()) {
            break;
        }
        if (first) {
            emit(log, LogLevel::warning, "auto-detect: the console does not answer yet; waiting for the dish to boot (up to " +
                                             std::to_string(boot_timeout.count() / 1000) + " s)");
        }
        if (elapsed() >= boot_timeout) {
            return {{}, Status{Errc::timeout, "auto-detect: no answer from the console within " +
                                                  std::to_string(boot_timeout.count() / 1000) +
                                                  " s; check wiring and baud (-s 57600 for Trav'ler/Carryout 2003, "
                                                  "-s 115200 for the G2) or choose the model yourself"}};
        }
        if (elapsed() >= next_progress) {
            next_progress += progress_interval;
            emit(log, LogLevel::verbose, "auto-detect: still waiting for the dish (" +
                                             std::to_string(elapsed().count() / 1000) + " s" +
                                             (session.last_boot_line().empty() ? std::string()
                                                                               : "; last boot output: " + session.last_boot_line()) +
                                             ")");
        }
    }

    // 2. Identify the menu from its help; climb out of submenus with `q` only where that is safe.
    bool left_odu_root = false;
    for (int level = 0; level < max_levels; ++level) {
        const std::vector<std::string> words = help_words(help.value.lines);
        emit(log, LogLevel::verbose, "auto-detect: prompt \"" + session.last_prompt() + "\", ? lists: " + listed(words));
        if (const auto found = variant_from_help(words)) {
            Detection d;
            d.variant = *found;
            d.evidence = "auto-detected: ? at prompt \"" + session.last_prompt() + "\" lists " +
                         std::string(profile(*found).help_signature.front());
            if (*found == VariantId::travler_hal000 && !left_odu_root && !lists_g2_root_command(words)) {
                // A Pro left in its ODU console shows the same menu. `q` is safe here (this is not a
                // G2 root); if it leads to the IDU, this is a Pro.
                session.set_menu("submenu");
                left_odu_root = true;
                if (const auto q = session.transact("q", help_timeout); !q && q.status.code != Errc::timeout) {
                    return {{}, q.status};
                }
                help = session.transact("?", help_timeout);
                if (help && variant_from_help(help_words(help.value.lines)) == VariantId::travler_pro) {
                    d.variant = VariantId::travler_pro;
                    d.evidence += "; q from there led to the IDU console (? lists odu): a Trav'ler Pro";
                } else {
                    d.maybe_pro_odu = true;
                    d.evidence += " (a Trav'ler Pro left inside its ODU console looks the same; elevation kept <= 75)";
                }
            }
            emit(log, LogLevel::verbose, d.evidence);
            return {d, Status::ok()};
        }
        // Never `q` where it could be the G2 root: its documented prompt, or any G2-only root command.
        if (words.empty() || lists_g2_root_command(words) || session.last_prompt() == "TRK>") {
            break;
        }
        // Not a root menu of any variant and not the G2 root: a submenu, which `q` leaves.
        session.set_menu("submenu");
        if (const auto q = session.transact("q", help_timeout); !q && q.status.code != Errc::timeout) {
            return {{}, q.status};
        }
        help = session.transact("?", help_timeout);
        if (!help && help.status.code != Errc::timeout) {
            return {{}, help.status};
        }
    }
    return {{}, Status{Errc::protocol, "auto-detect: the console's help matches no known Winegard firmware (last prompt \"" +
                                           session.last_prompt() + "\"); choose the model yourself"}};
}

}  // namespace birdcage
