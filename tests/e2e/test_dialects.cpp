// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Generated consoles (label `dialects`): the emulator's dialect generator draws a console per
// seed (sim/README.md, "Dialects"), and the stock /usr/bin/rotctld with the backend preloaded must
// open it — with the variant's own model and with auto-detect 90100, at a dish already up and at
// one that is booting (one way per seed in CI, see ways_for) — then `P` moves the dish to the
// target, `p` reports it, and the emulator counted no hazard.
//
// The seeds are a fixed list so that CI is deterministic; scripts/dialect-soak.sh runs others
// through BIRDCAGE_DIALECT_SEEDS. Each cell is a Catch2 test case of its own (ctest runs them in
// parallel and names a failing one exactly). Cells listed in dialects-known-failing.txt are hidden
// from ctest (tag [.][known-failing]) and run by hand: `test_dialects "[known-failing]"`.
#include "harness.hpp"

#include <birdcage_sim/dialect.hpp>
#include <birdcage_sim/transcript.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace std::chrono_literals;
using birdcage::sim::Emulator;
using birdcage::sim::Options;
using birdcage::sim::Variant;

namespace {

constexpr int kAutoDetectModel = 90100;
constexpr double kTolerance = 0.1;  // as the first-contact matrix: two decimals + the G2 deadband

struct VariantRow {
    Variant variant;
    const char* name;
    int own_model;
    const char* detected_as;  // what get_info names when 90100 identified this variant
    int baud;                 // -s for auto-detect
};

const std::vector<VariantRow> kVariants = {
    {Variant::travler_hal000, "hal000", 90101, "HAL 0.0.00", 57600},
    {Variant::travler_hal205, "hal205", 90102, "HAL 2.05", 57600},
    {Variant::travler_pro, "pro", 90103, "Trav'ler Pro", 57600},
    {Variant::carryout2003, "carryout2003", 90104, "Carryout HAL 1.00.065", 57600},
    {Variant::carryout_g2, "g2", 90105, "Carryout G2", 115200},
};

// Simulated seconds per real one. A drawn boot is up to 90 simulated seconds (3 s here) and a
// drawn boot silence of 5 s lasts 0.17 s on the line, longer than the silence that ends a reply
// for the backend (150 ms, real time), so silences of several seconds still look like silences.
constexpr double kTimeScale = 30.0;

// rotctld opens the dish before it listens: the longest drawn boot (3 s here) and first contact.
constexpr auto kOpenWithin = 15s;
// Failure bounds in real time, not timing assertions: a cell that passes waits only for its
// conditions, and a loaded machine (the sanitizer build, parallel cells) must not fail one. The
// dish's own motion is in simulated time: the slowest drawn motor takes about 30 simulated seconds
// to the target (1 s here), a dish still moving at start some more.
constexpr auto kAcceptedWithin = 30s;  // `P` answered RPRT 0 (retried while the backend still opens)
constexpr auto kSettledWithin = 60s;   // the dish at rest on the target
constexpr auto kReportedWithin = 30s;  // `p` reports it

// The CI seed list: seeds 1..30 for every variant.
constexpr std::uint32_t kFirstSeed = 1, kSeedsPerVariant = 30;

enum class Meeting { dish_up, booting };

// The ways of meeting a console: (own model, 90100) x (dish up, booting). One cell per seed keeps
// the label near 6 minutes on two cores; the way turns with the seed, so across the 30 seeds of a
// variant each way meets 7 or 8 consoles. The soak script meets every seed all four ways.
struct Way {
    Meeting meeting;
    bool auto_detect;
};
const Way kAllWays[] = {
    {Meeting::dish_up, false}, {Meeting::booting, true}, {Meeting::booting, false}, {Meeting::dish_up, true}};
std::vector<Way> ways_for(std::uint32_t seed) {
    if (std::getenv("BIRDCAGE_DIALECT_ALL_WAYS") != nullptr)
        return {std::begin(kAllWays), std::end(kAllWays)};
    return {kAllWays[seed % 4]};
}

std::string meeting_name(Meeting m) {
    return m == Meeting::dish_up ? "dish up" : "booting";
}

std::string cell_name(const VariantRow& v, std::uint32_t seed, const Way& way) {
    std::ostringstream name;
    name << v.name << " seed " << seed << " / " << meeting_name(way.meeting) << " / "
         << (way.auto_detect ? "auto 90100" : "own " + std::to_string(v.own_model));
    return name.str();
}

std::string tail(const std::string& text, std::size_t bytes) {
    return text.size() <= bytes ? text : "...\n" + text.substr(text.size() - bytes);
}

// The console transcript as --trace prints it: `<<` client bytes, `>>` dish bytes.
class Transcript {
public:
    void add(bool from_client, std::string_view bytes) {
        const std::lock_guard lock(mutex_);
        if (from_client != last_from_client_ || text_.empty() || text_.back() == '\n') {
            text_ += text_.empty() ? "" : "\n";
            text_ += from_client ? "<< " : ">> ";
        }
        last_from_client_ = from_client;
        text_ += birdcage::sim::escape_chunk(bytes);
    }
    std::string text() const {
        const std::lock_guard lock(mutex_);
        return text_;
    }

private:
    mutable std::mutex mutex_;
    std::string text_;
    bool last_from_client_ = false;
};

// BIRDCAGE_DIALECT_TRANSCRIPT=full (the soak script) prints the whole transcript on failure.
std::size_t transcript_bytes() {
    const char* full = std::getenv("BIRDCAGE_DIALECT_TRANSCRIPT");
    return full != nullptr && std::string(full) == "full" ? std::string::npos : 6000;
}

std::string where(Emulator& dish) {
    const birdcage::sim::Pose p = dish.true_position();
    std::ostringstream out;
    out << "dish at az " << p.az << " el " << p.el << (dish.moving() ? " (moving)" : " (at rest)") << ", sim time "
        << dish.sim_time() << " s, hazards " << dish.hazards_received() << ", shell "
        << (dish.shell_alive() ? "alive" : "DEAD");
    return out.str();
}

void run_cell(const VariantRow& v, std::uint32_t seed, const Way& way) {
    const birdcage::sim::Dialect dialect = birdcage::sim::draw_dialect(v.variant, seed);
    Options o = dialect.options;
    o.time_scale = kTimeScale;
    o.start_az = 100.0;
    o.start_el = 30.0;
    o.already_booted = way.meeting == Meeting::dish_up;
    // The asynchronous line's period is drawn in seconds of a real dish and competes with the
    // backend's real-time reply windows, so it stays real (as in the first-contact matrix): at
    // 30x a line every 3 s would otherwise arrive every 0.1 s.
    o.idle_line_period *= kTimeScale;
    // A 2003 Carryout whose search is off (all DIP switches up, docs/firmware.md §8.2), as in the
    // first-contact matrix: a search cannot be stopped nor seen from the console.
    if (v.variant == Variant::carryout2003)
        o.carryout_search_seconds = 0.0;
    auto transcript = std::make_shared<Transcript>();
    o.trace = [transcript](bool from_client, std::string_view bytes) { transcript->add(from_client, bytes); };

    std::vector<std::string> args = {"-C", "time_scale=" + std::to_string(kTimeScale)};
    if (way.auto_detect)
        args.insert(args.end(), {"-s", std::to_string(v.baud)});
    const int model = way.auto_detect ? kAutoDetectModel : v.own_model;

    INFO("the drawn console (birdcage-sim --variant " << v.name << " --dialect describe --seed " << seed << "):\n"
                                                      << dialect.description);
    std::unique_ptr<e2e::Rig> rig;
    try {
        rig = std::make_unique<e2e::Rig>(o, model, args, nullptr, kOpenWithin);
    } catch (const std::exception& e) {
        FAIL("rotctld did not open the dish; its log:\n"
             << tail(e.what(), 4000) << "\nconsole transcript:\n"
             << tail(transcript->text(), transcript_bytes()));
    }
    INFO("console transcript:\n" << tail(transcript->text(), transcript_bytes()));
    e2e::RotctldConnection client(rig->port());
    if (way.auto_detect) {
        const std::string info = client.ask("_", 1, kAcceptedWithin);
        INFO("get_info: " << info);
        CHECK(info.find(v.detected_as) != std::string::npos);
    }

    const double target_az = 150.0, target_el = 40.0;
    std::string reply;
    const bool accepted = e2e::wait_until(
        [&] {
            reply = client.ask("P 150 40", 1);
            return reply == "RPRT 0\n";
        },
        kAcceptedWithin);
    INFO("P reply: " << reply << "; " << where(rig->dish()));
    INFO("rotctld log, last part:\n" << tail(rig->rotctld_log_text(), 3000));
    REQUIRE(accepted);
    const bool settled =
        e2e::wait_until([&] { return e2e::settled_at(rig->dish(), target_az, target_el, kTolerance); }, kSettledWithin);
    INFO(where(rig->dish()));
    REQUIRE(settled);
    e2e::RotctldConnection::Position reported;
    const bool reports = e2e::wait_until(
        [&] {
            reported = client.get_position();
            return reported.ok && e2e::angle_between(reported.az, target_az) <= kTolerance &&
                   std::fabs(reported.el - target_el) <= kTolerance;
        },
        kReportedWithin);
    INFO("p: " << (reported.ok ? std::to_string(reported.az) + " " + std::to_string(reported.el) : reported.error));
    CHECK(reports);
    CHECK(rig->dish().hazards_received() == 0);
    CHECK(rig->dish().shell_alive());
    CHECK(rig->rotctld_running());
}

class Cell : public Catch::ITestInvoker {
public:
    Cell(const VariantRow& v, std::uint32_t seed, Way way) : variant_(v), seed_(seed), way_(way) {}
    void invoke() const override { run_cell(variant_, seed_, way_); }

private:
    const VariantRow& variant_;
    std::uint32_t seed_;
    Way way_;
};

// dialects-known-failing.txt: one cell name per line, `#` starts a comment (the cause).
std::set<std::string> known_failing() {
    std::set<std::string> names;
    std::ifstream in(BIRDCAGE_DIALECTS_KNOWN_FAILING);
    for (std::string line; std::getline(in, line);) {
        line = line.substr(0, line.find('#'));
        while (!line.empty() && (line.back() == ' ' || line.back() == '\t'))
            line.pop_back();
        if (!line.empty())
            names.insert(line);
    }
    return names;
}

// BIRDCAGE_DIALECT_SEEDS="A-B" or "A,B,C" replaces the CI list (the soak script).
std::vector<std::uint32_t> seeds() {
    std::vector<std::uint32_t> list;
    const char* spec = std::getenv("BIRDCAGE_DIALECT_SEEDS");
    if (spec == nullptr || *spec == '\0') {
        for (std::uint32_t s = kFirstSeed; s < kFirstSeed + kSeedsPerVariant; ++s)
            list.push_back(s);
        return list;
    }
    std::istringstream in(spec);
    for (std::string part; std::getline(in, part, ',');) {
        const auto dash = part.find('-');
        const auto first = static_cast<std::uint32_t>(std::stoul(part.substr(0, dash)));
        const auto last =
            dash == std::string::npos ? first : static_cast<std::uint32_t>(std::stoul(part.substr(dash + 1)));
        for (std::uint32_t s = first; s <= last; ++s)
            list.push_back(s);
    }
    return list;
}

struct Registrar {
    Registrar() {
        const std::set<std::string> known = known_failing();
        for (const VariantRow& v : kVariants) {
            for (const std::uint32_t seed : seeds()) {
                for (const Way& way : ways_for(seed)) {
                    const std::string name = cell_name(v, seed, way);
                    const std::string tags = std::string("[e2e][dialects][") + v.name + "]" +
                                             (known.count(name) != 0 ? "[.][known-failing]" : "");
                    Catch::AutoReg(new Cell(v, seed, way), CATCH_INTERNAL_LINEINFO, Catch::StringRef(),
                                   Catch::NameAndTags{name, tags});
                }
            }
        }
    }
};

const Registrar registrar;

}  // namespace
