// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage-probe against the emulated G2: the report lists every submenu docs/firmware.md 6.3 lists,
// with its prompt, and the dish sees no hazard. `record` tees a piped session into a transcript.
// --deep finds the commands the emulator accepts but leaves out of `?`, sends no hazard and does
// not move the dish.
#include <catch2/catch.hpp>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "birdcage_sim/dialect.hpp"
#include "birdcage_sim/emulator.hpp"
#include "birdcage_sim/transcript.hpp"
#include "console/port_lock.hpp"

namespace sim = birdcage::sim;

namespace {

// The command's stdout; its exit status in `status`.
std::string run_with_status(const std::string& command, int& status) {
    std::string output;
    FILE* pipe = ::popen(command.c_str(), "r");
    REQUIRE(pipe != nullptr);
    std::array<char, 4096> buffer{};
    while (const std::size_t count = std::fread(buffer.data(), 1, buffer.size(), pipe))
        output.append(buffer.data(), count);
    const int raw = ::pclose(pipe);
    status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    return output;
}

std::string run(const std::string& command) {
    int status = 0;
    std::string output = run_with_status(command, status);
    CHECK(status == 0);
    return output;
}

// Types console lines into the dish as a user at a terminal would, each once the previous one's
// reply has gone quiet: to leave the console inside a submenu before the probe arrives.
void type_into(sim::Emulator& dish, const std::vector<std::string>& lines) {
    const int fd = ::open(dish.device_path().c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
    REQUIRE(fd >= 0);
    for (const std::string& line : lines) {
        const std::size_t before = dish.received_commands().size();
        const std::string wire = line + "\r";
        REQUIRE(::write(fd, wire.data(), wire.size()) == static_cast<ssize_t>(wire.size()));
        std::array<char, 512> buffer{};
        // Read until the dish took the line and said nothing for 3 polls (a chatty console: 40 polls).
        for (int quiet = 0, polls = 0; quiet < 3 && polls < 40; ++polls) {
            pollfd ready{fd, POLLIN, 0};
            const bool data = ::poll(&ready, 1, 50) > 0 && ::read(fd, buffer.data(), buffer.size()) > 0;
            quiet = data || dish.received_commands().size() == before ? 0 : quiet + 1;
        }
        REQUIRE(dish.received_commands().size() > before);
    }
    ::close(fd);
}

// One JSON string field of the report (the first), or "<absent>".
std::string field(const std::string& report, const std::string& name) {
    const std::string key = "\"" + name + "\": ";
    const std::size_t at = report.find(key);
    if (at == std::string::npos)
        return "<absent>";
    const std::size_t start = at + key.size();
    if (report.compare(start, 4, "null") == 0)
        return "null";
    const std::size_t end = report.find('"', start + 1);
    return report.substr(start + 1, end - start - 1);
}

sim::Emulator make_g2() {
    sim::Options options;
    options.variant = sim::Variant::carryout_g2;
    options.time_scale = 20.0;
    return sim::Emulator(options);
}

}  // namespace

TEST_CASE("birdcage-probe maps every G2 submenu with its prompt and sends no hazard") {
    sim::Options options;
    options.variant = sim::Variant::carryout_g2;
    options.time_scale = 20.0;
    sim::Emulator dish(options);
    const std::string report =
        run(std::string(BIRDCAGE_PROBE_PATH) + " --port " + dish.device_path() + " --variant g2");

    // The emulator's pty passes bytes at any speed: the probe names none and tries no other.
    CHECK_THAT(report, Catch::Contains("\"line\": \"pty\",\n  \"baud\": null,\n  \"bauds_tried\": []"));
    CHECK_THAT(report, Catch::Contains("\"root_prompt\": \"TRK>\""));
    CHECK_THAT(report, Catch::Contains("\"error_string\": \"Invalid command\""));  // the captured G2's
    const std::array<std::pair<const char*, const char*>, 12> submenus{{
        {"a3981", "A3981>"},
        {"adc", "ADC>"},
        {"dipswitch", "DIPSWITCH>"},
        {"dvb", "DVB>"},
        {"eeprom", "EE>"},
        {"gpio", "GPIO>"},
        {"latlon", "LATLON>"},
        {"mot", "MOT>"},
        {"nvs", "NVS>"},
        {"os", "OS>"},
        {"peak", "PEAK>"},
        {"step", "STEP>"},
    }};
    for (const auto& [name, prompt] : submenus) {
        INFO(name);
        CHECK_THAT(report, Catch::Contains(std::string("{\"name\": \"") + name + "\", \"prompt\": \"" + prompt + "\""));
    }
    // The help trap: `help [<command>]` is usage, not a command and not a prompt.
    CHECK_THAT(report, !Catch::Contains("\"name\": \"help\""));
    // The captured root lists its 12 submenus only: no `reboot` or `stow` there.
    const std::string root_help =
        report.substr(report.find("\"root_help\""), report.find("\"menus\"") - report.find("\"root_help\""));
    CHECK_THAT(root_help, !Catch::Contains("\"name\": \"reboot\""));
    CHECK_THAT(root_help, !Catch::Contains("\"name\": \"stow\""));
    CHECK_THAT(report, Catch::Contains("\"variant\": {\"name\": \"g2\""));
    CHECK_THAT(report, Catch::Contains("\"final_prompt\": \"TRK>\""));
    CHECK(dish.hazards_received() == 0);
    CHECK(dish.shell_alive());
}

namespace {

struct StartingPoint {
    sim::Variant variant;
    const char* probe_variant;  // the report's variant, or "" where the root is also the Pro's inner console
    std::vector<std::vector<std::string>> typed;  // the lines that leave the console in a submenu
    const char* root_prompt;
};

// The probe arrives where a user or rotctld left the console: it leaves the submenu with `q`,
// maps the root, names the variant, and the dish receives no word of the hazard rule.
void probe_from(const sim::Options& options, const std::vector<std::string>& typed, const char* root_prompt,
                const char* variant_name, bool walk_returns = true) {
    sim::Emulator dish(options);
    type_into(dish, typed);
    const std::size_t typed_lines = dish.received_commands().size();
    int status = -1;
    const std::string report = run_with_status(
        std::string(BIRDCAGE_PROBE_PATH) + " --port " + dish.device_path() + " --baud 115200 2>/dev/null", status);
    INFO("typed " << typed.size() << " line(s), last: " << (typed.empty() ? "" : typed.back()) << "\n" << report);
    CHECK(status == 0);
    CHECK(field(report, "root_prompt") == root_prompt);
    if (walk_returns) {
        CHECK(field(report, "final_prompt") == root_prompt);
        CHECK(field(report, "stopped") == "null");
    } else {
        CHECK_THAT(field(report, "stopped"), Catch::Contains("did not return"));
    }
    if (*variant_name != '\0')
        CHECK_THAT(report, Catch::Contains(std::string("\"variant\": {\"name\": \"") + variant_name + "\""));
    const auto received = dish.received_commands();
    const auto hazards = dish.hazard_commands();
    INFO("hazards: " << hazards.size() << (hazards.empty() ? "" : " first: " + hazards.front()));
    CHECK(dish.hazards_received() == 0);
    CHECK(dish.shell_alive());
    // Where the console was left in a submenu, `q` was the first word the probe sent.
    if (!typed.empty()) {
        std::size_t first = typed_lines;
        // The synchroniser's bare line endings, and its `?` when a poke drew no prompt in time.
        while (first < received.size() && (received[first].empty() || received[first] == "?"))
            ++first;
        REQUIRE(first < received.size());
        CHECK(received[first] == "q");
    }
}

sim::Options own(sim::Variant variant) {
    sim::Options options;
    options.variant = variant;
    options.time_scale = 20.0;
    return options;
}

}  // namespace

// One test case per few starting points: ctest runs them side by side (each mostly waits on the
// line).
TEST_CASE("birdcage-probe at G2 submenu prompts (1/3): leaves with q and maps the root with no hazard", "[submenus]") {
    for (const char* menu : {"a3981", "adc", "dipswitch", "dvb"})
        probe_from(own(sim::Variant::carryout_g2), {menu}, "TRK>", "g2");
}

TEST_CASE("birdcage-probe at G2 submenu prompts (2/3): leaves with q and maps the root with no hazard", "[submenus]") {
    for (const char* menu : {"eeprom", "gpio", "latlon", "mot"})
        probe_from(own(sim::Variant::carryout_g2), {menu}, "TRK>", "g2");
}

TEST_CASE("birdcage-probe at G2 submenu prompts (3/3): leaves with q and maps the root with no hazard", "[submenus]") {
    for (const char* menu : {"nvs", "os", "peak", "step"})
        probe_from(own(sim::Variant::carryout_g2), {menu}, "TRK>", "g2");
}

TEST_CASE("birdcage-probe at every Trav'ler HAL submenu prompt sends no hazard", "[submenus]") {
    for (const char* menu : {"mot", "nvs", "os"})
        probe_from(own(sim::Variant::travler_hal000), {menu}, "TRK>", "hal000");
    for (const char* menu : {"motor", "ngsearch", "nvs", "os"})
        probe_from(own(sim::Variant::travler_hal205), {menu}, "TRK>", "hal205");
}

TEST_CASE("birdcage-probe behind a bare root whose submenus name themselves walks the menus", "[submenus]") {
    sim::Options options = own(sim::Variant::travler_hal000);
    options.prompt_style = sim::PromptStyle::bare_root;
    // Left in MOT>: out with `q` to `>`, which the probe now tells from a submenu.
    probe_from(options, {"mot"}, ">", "");
    sim::Emulator dish(options);
    type_into(dish, {"mot"});
    int status = -1;
    const std::string report = run_with_status(
        std::string(BIRDCAGE_PROBE_PATH) + " --port " + dish.device_path() + " --baud 115200 2>/dev/null", status);
    INFO(report);
    CHECK(status == 0);
    CHECK_THAT(report, !Catch::Contains("could not tell a submenu"));
    CHECK_THAT(report, Catch::Contains("\"prompt\": \"MOT>\"") && Catch::Contains("\"prompt\": \"NVS>\""));
    CHECK(dish.hazards_received() == 0);
    // At the root from the start, nothing shows how submenus look: it enters none and says why.
    sim::Emulator at_root(options);
    const std::string unseen = run_with_status(
        std::string(BIRDCAGE_PROBE_PATH) + " --port " + at_root.device_path() + " --baud 115200 2>/dev/null", status);
    INFO(unseen);
    CHECK_THAT(unseen, Catch::Contains("no submenu was seen naming itself"));
    CHECK(at_root.hazards_received() == 0);
}

TEST_CASE("birdcage-probe at every Carryout 2003 and Trav'ler Pro submenu prompt sends no hazard", "[submenus]") {
    for (const char* menu : {"target", "motor", "dvb", "os", "nvs"})
        probe_from(own(sim::Variant::carryout2003), {menu}, "TRK>", "carryout2003");
    // The Pro at its IDU root: it walks into the ODU console and, where `q` there does not lead
    // back (the open question of docs/firmware.md §14), says so instead of wandering on.
    probe_from(own(sim::Variant::travler_pro), {}, "IDU>", "pro", false);
    // Inside its ODU console, whose root looks like HAL 0.0.00's: the report names hal000 and
    // "or_inside": "pro".
    for (const char* menu : {"mot", "nvs", "os"})
        probe_from(own(sim::Variant::travler_pro), {"odu", menu}, "TRK>", "hal000");
}

namespace {

// A generated console (the dialect generator's, sim/README.md "Dialects") left in its motor menu.
void probe_dialects(sim::Variant variant, const char* menu) {
    for (const std::uint32_t seed : {3u, 7u, 11u}) {
        sim::Options options = sim::draw_dialect(variant, seed).options;
        options.time_scale = 20.0;
        options.already_booted = true;
        // Its status lines come every few simulated seconds, a fraction of a real second at 20x:
        // more often than any reply's quiet. Prompts and menus are what is tried here.
        options.idle_line.clear();
        INFO(sim::variant_name(variant) << " seed " << seed);
        sim::Emulator dish(options);
        type_into(dish, {menu});
        int status = -1;
        const std::string report = run_with_status(
            std::string(BIRDCAGE_PROBE_PATH) + " --port " + dish.device_path() + " --baud 115200 2>/dev/null", status);
        INFO(report);
        CHECK(dish.hazards_received() == 0);
        CHECK(dish.shell_alive());
        const bool named = options.prompt_style == sim::PromptStyle::named || variant == sim::Variant::carryout_g2;
        if (options.prompt_style == sim::PromptStyle::bare_root) {
            // `>` at the root only: the probe left the named menu, so it tells a submenu from the
            // root and walks the menus.
            CHECK(status == 0);
            CHECK(field(report, "root_prompt").find("TRK") == std::string::npos);
            CHECK_THAT(field(report, "final_prompt"), !Catch::Contains("MOT") && !Catch::Contains("MOTOR"));
            CHECK_THAT(report, !Catch::Contains("could not tell a submenu"));
        } else if (named) {
            // A named prompt, decorated or not: out of the menu, at the root, the variant named
            // (or, where the evidence is thin, left unnamed; never a wrong one).
            CHECK(status == 0);
            CHECK_THAT(field(report, "root_prompt"), Catch::Contains("TRK>"));  // as shown, decorations included
            CHECK_THAT(report,
                       Catch::Contains(std::string("\"variant\": {\"name\": \"") + sim::variant_name(variant) + "\"") ||
                           Catch::Contains("\"variant\": {\"name\": null"));
        } else {
            // `>` everywhere: the probe cannot tell the menu from the root and says so.
            CHECK(status == 1);
            CHECK(field(report, "stopped") != "null");
        }
    }
}

}  // namespace

TEST_CASE("birdcage-probe on generated G2 consoles left in MOT> sends no hazard", "[submenus][dialects]") {
    probe_dialects(sim::Variant::carryout_g2, "mot");
}

TEST_CASE("birdcage-probe on generated Trav'ler consoles left in their motor menu sends no hazard",
          "[submenus][dialects]") {
    probe_dialects(sim::Variant::travler_hal000, "mot");
    probe_dialects(sim::Variant::travler_hal205, "motor");
}

TEST_CASE("birdcage-probe on generated Carryout 2003 consoles left in TARGET> sends no hazard",
          "[submenus][dialects]") {
    probe_dialects(sim::Variant::carryout2003, "target");
}

TEST_CASE("birdcage-probe refuses a port another process holds or a live lock file names", "[busy]") {
    sim::Emulator dish = make_g2();
    const std::string probe = std::string(BIRDCAGE_PROBE_PATH) + " --port " + dish.device_path() + " --baud 115200";

    SECTION("another process has the device open (as rotctld with the backend has)") {
        FILE* holder = ::popen(("exec 3<>" + dish.device_path() + "; read line").c_str(), "w");
        REQUIRE(holder != nullptr);
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (birdcage::other_port_holders(dish.device_path()).empty() && std::chrono::steady_clock::now() < deadline)
            ::poll(nullptr, 0, 10);
        int status = -1;
        const std::string report = run_with_status(probe + " 2>&1", status);
        ::pclose(holder);
        INFO(report);
        CHECK(status == 3);
        CHECK_THAT(report, Catch::Contains("is busy") && Catch::Contains("has it open"));
    }
    SECTION("a lock file names a live process; a stale one is replaced and removed") {
        const auto dir = std::filesystem::temp_directory_path() / ("birdcage-lock-" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir);
        const auto lock = dir / birdcage::lock_file_name(dish.device_path());
        char text[16];
        std::snprintf(text, sizeof text, "%10d\n", static_cast<int>(::getppid()));
        std::ofstream(lock) << text;
        int status = -1;
        const std::string busy = run_with_status("BIRDCAGE_LOCK_DIR=" + dir.string() + " " + probe + " 2>&1", status);
        INFO(busy);
        CHECK(status == 3);
        CHECK_THAT(busy, Catch::Contains("is locked by PID"));

        const pid_t gone = ::fork();
        if (gone == 0)
            ::_exit(0);
        ::waitpid(gone, nullptr, 0);
        std::snprintf(text, sizeof text, "%10d\n", static_cast<int>(gone));
        std::ofstream(lock, std::ios::trunc) << text;
        const std::string report =
            run_with_status("BIRDCAGE_LOCK_DIR=" + dir.string() + " " + probe + " 2>/dev/null", status);
        CHECK(status == 0);
        CHECK(field(report, "root_prompt") == "TRK>");
        CHECK_FALSE(std::filesystem::exists(lock));  // released at exit
        std::filesystem::remove_all(dir);
    }
    CHECK(dish.hazards_received() == 0);
}

TEST_CASE("birdcage-probe record tees a piped session into a transcript and refuses root q") {
    sim::Emulator dish = make_g2();
    const auto path =
        std::filesystem::temp_directory_path() / ("birdcage-record-" + std::to_string(::getpid()) + ".log");
    run("printf 'mot\\na\\nq\\nq\\n' | " + std::string(BIRDCAGE_PROBE_PATH) + " record --variant g2 --port " +
        dish.device_path() + " --output " + path.string() + " 2>/dev/null");

    const auto transcript = sim::load_transcript(path.string());
    std::filesystem::remove(path);
    CHECK(transcript.header("Variant") == "g2");
    CHECK(transcript.header("Serial") == "115200 8N1");
    std::string host, dish_bytes;
    for (const auto& entry : transcript.entries)
        (entry.direction == sim::Direction::host_to_dish ? host : dish_bytes) += entry.bytes;
    CHECK(host == "mot\ra\rq\r");  // the second q would have been at TRK>
    CHECK_THAT(dish_bytes, Catch::Contains("Angle[0] = 180.00"));
    CHECK(dish.hazards_received() == 0);
    CHECK(dish.shell_alive());
}

TEST_CASE("birdcage-probe without --variant waits for a booting G2 through the console synchroniser") {
    sim::Options options;
    options.variant = sim::Variant::carryout_g2;
    options.time_scale = 10.0;
    options.already_booted = false;
    sim::Emulator dish(options);
    const std::string report =
        run(std::string(BIRDCAGE_PROBE_PATH) + " --port " + dish.device_path() + " --baud 115200");

    // The root prompt is the one confirmed after the boot, not a stale line read mid-boot.
    CHECK_THAT(report, Catch::Contains("\"root_prompt\": \"TRK>\""));
    CHECK_THAT(report, Catch::Contains("{\"name\": \"mot\", \"prompt\": \"MOT>\""));
    CHECK(dish.hazards_received() == 0);
    CHECK(dish.shell_alive());
}

namespace {

// The "deep" object's entry for one menu, up to the next menu.
std::string deep_menu(const std::string& report, const std::string& menu) {
    const std::size_t deep = report.find("\"deep\": {");
    REQUIRE(deep != std::string::npos);
    const std::size_t start = report.find("{\"menu\": \"" + menu + "\"", deep);
    REQUIRE(start != std::string::npos);
    const std::size_t end = report.find("{\"menu\": ", start + 1);
    return report.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

}  // namespace

TEST_CASE("birdcage-probe --deep finds the commands a G2 accepts but does not list, and never moves it") {
    sim::Options options;
    options.variant = sim::Variant::carryout_g2;
    options.time_scale = 20.0;
    options.g2_console = sim::G2Console::reconstructed;  // hiding `l` and `dis` from `?` is the reconstruction's switch
    options.unlisted_commands = true;
    sim::Emulator dish(options);
    const sim::Pose before = dish.true_position();
    const std::string report = run(std::string(BIRDCAGE_PROBE_PATH) + " --port " + dish.device_path() +
                                   " --variant g2 --deep --submenu mot --submenu dvb --submenu nvs 2>/dev/null");

    // `?` does not list them ...
    CHECK_THAT(report, !Catch::Contains("{\"name\": \"l\""));
    CHECK_THAT(report, !Catch::Contains("{\"name\": \"dis\""));
    // ... deep discovery finds them, each in its own menu, with its reply.
    const std::string mot = deep_menu(report, "mot");
    CHECK_THAT(mot, Catch::Contains("\"prompt\": \"MOT>\", \"unknown_reply\": [\"Unknown command\"]"));
    CHECK_THAT(mot, Catch::Contains("{\"word\": \"l\", \"reply\": [\"0 AZIMUTH\", \"1 ELEVATION\"]}"));
    CHECK_THAT(mot, !Catch::Contains("\"word\": \"dis\""));
    const std::string dvb = deep_menu(report, "dvb");
    CHECK_THAT(dvb, Catch::Contains("{\"word\": \"dis\", \"reply\": [\"Freq:"));
    CHECK_THAT(dvb, !Catch::Contains("\"word\": \"l\""));
    // NVS> reads the next index for any unknown word: there is nothing to compare with.
    CHECK_THAT(deep_menu(report, "nvs"), Catch::Contains("answers two unknown words differently"));
    // The motion words of the built-in list are reported, not sent.
    CHECK_THAT(report, Catch::Contains("{\"word\": \"g\", \"reason\": \"moves: "));
    CHECK_THAT(report, Catch::Contains("{\"word\": \"e\", \"reason\": \"releases: "));
    CHECK_THAT(report, Catch::Contains("{\"word\": \"agc\", \"reason\": \"streams"));
    CHECK_THAT(report, Catch::Contains("\"stopped\": null"));
    CHECK_THAT(report, Catch::Contains("\"final_prompt\": \"TRK>\""));
    for (const auto& line : dish.received_commands()) {
        INFO(line);
        const std::string verb = line.substr(0, line.find(' '));
        CHECK(verb != "g");
        CHECK(verb != "h");
        CHECK(verb != "agc");
    }
    const sim::Pose after = dish.true_position();
    CHECK(std::fabs(after.az - before.az) < 1e-9);
    CHECK(std::fabs(after.el - before.el) < 1e-9);
    CHECK(!dish.moving());
    CHECK(dish.hazards_received() == 0);
    CHECK(dish.shell_alive());
}

TEST_CASE("birdcage-probe --deep accepts nothing unlisted where the emulator hides nothing") {
    // The reconstructed console with unlisted_commands off: `l` is an unknown command.
    sim::Options options;
    options.variant = sim::Variant::carryout_g2;
    options.time_scale = 20.0;
    options.g2_console = sim::G2Console::reconstructed;
    sim::Emulator dish(options);
    const std::string report = run(std::string(BIRDCAGE_PROBE_PATH) + " --port " + dish.device_path() +
                                   " --variant g2 --deep --submenu mot 2>/dev/null");
    const std::string mot = deep_menu(report, "mot");
    CHECK_THAT(mot, Catch::Contains("\"accepted\": []"));
    CHECK_THAT(mot, !Catch::Contains("\"tried\": 0,"));
    CHECK(dish.hazards_received() == 0);
}

TEST_CASE("birdcage-probe --deep never sends a hazard or an argument, whatever the word list says") {
    sim::Options options;
    options.variant = sim::Variant::carryout_g2;
    options.time_scale = 20.0;
    options.g2_console = sim::G2Console::reconstructed;  // `stow`/`reboot` at the root, `l` unlisted
    options.unlisted_commands = true;
    sim::Emulator dish(options);
    const auto path =
        std::filesystem::temp_directory_path() / ("birdcage-words-" + std::to_string(::getpid()) + ".txt");
    {
        std::ofstream words(path);
        words << "# hazards and arguments first\nstow\nreboot\ndef\ninv\nscan\nq\nQ\ng 10 20\na 0 90\nl\n";
    }
    // Without --variant the guard judges with the G2's rules; the root walk itself sends no hazard.
    const std::string report =
        run(std::string(BIRDCAGE_PROBE_PATH) + " --port " + dish.device_path() + " --baud 115200 --deep --wordlist " +
            path.string() + " --submenu root --submenu mot --submenu eeprom 2>/dev/null");
    std::filesystem::remove(path);

    // Words the hazard rule names in any menu of any variant are reported, not sent.
    for (const char* hazard : {"stow", "reboot", "def", "inv", "scan", "Q"}) {
        INFO(hazard);
        CHECK_THAT(report, Catch::Contains(std::string("{\"word\": \"") + hazard + "\", \"reason\": \""));
    }
    CHECK_THAT(report, Catch::Contains("{\"word\": \"g 10 20\", \"reason\": \"more than one word"));
    CHECK_THAT(report, Catch::Contains("{\"word\": \"a 0 90\", \"reason\": \"more than one word"));
    CHECK_THAT(deep_menu(report, "mot"), Catch::Contains("{\"word\": \"l\""));
    for (const auto& line : dish.received_commands()) {
        INFO(line);
        CHECK(line.find(' ') == std::string::npos);  // no arguments
    }
    CHECK_THAT(report, Catch::Contains("\"final_prompt\": \"TRK>\""));
    CHECK(dish.hazards_received() == 0);
    CHECK(dish.shell_alive());
}
