// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage-tui: a terminal dashboard and control panel for any rotator behind rotctld, with the
// Winegard extras (signal, LNB, homing, variant) where the backend offers them. A client of
// rotctld, so it runs beside Gpredict. docs/tui.md shows the screens.
#include "birdcage_version.hpp"
#include "cli_args.hpp"
#include "scan_launcher.hpp"
#include "sky_tracker.hpp"
#include "station.hpp"

#include <curses.h>

#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <deque>
#include <fstream>
#include <iostream>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace tui = birdcage::tui;

namespace {

const char* const usage_text = R"(Usage: birdcage-tui [--host H] [--port P] [--log FILE] [sky options]

A terminal UI for a rotator behind rotctld (any Hamlib rotator; the Winegard dish's signal, LNB,
homing and variant where the birdcage backend offers them). It is one more rotctld client, so it
runs beside Gpredict or any other. It reconnects by itself when rotctld restarts.

  --host H      rotctld's host (default localhost)
  --port P      rotctld's TCP port (default 4533)
  --log FILE    show the tail of this file on the info screen (e.g. rotctld's log)
  --help        this text
  --version     the program's version

The sky screen runs birdcage-track (passes, what is up, tracking); it is given --host/--port and:
  --track-program PATH  birdcage-track (default: beside this program, else on PATH)
  --lat DEG --lon DEG   the station (east positive); default: BIRDCAGE_LAT/BIRDCAGE_LON
  --alt M               the station's altitude; default: BIRDCAGE_ALT
  --tle FILE|DIR        TLEs to read (repeatable; default: Gpredict's)
  --at ISO-TIME         rehearsal: the sky's clock starts at this UTC time...
  --time-scale K        ...and runs K times faster (as the emulator's -C time_scale)

Screens: 1 dashboard, 2 control, 3 signal, 4 info, 5 sky (Tab cycles).
Keys on every screen: arrows jog by the step, +/- choose the step (0.1, 1, 5, 10 deg),
g go to AZ EL, s stop (a track too), k park, h home (R, where the rotator can), q quit.
Signal screen: l toggles the LNB supply 13/18 V, n starts a sky scan (birdcage-skyscan), x stops it.
Sky screen: [ ] choose a target, p its passes, t track it, x stop tracking, r refresh.
While a track runs, moves (g, arrows, k, h, n) are refused: x or s ends it first.
)";

int usage_error(const std::string& message) {
    std::cerr << "birdcage-tui: " << message << " (see --help)\n";
    return 2;
}

volatile std::sig_atomic_t quit_signal = 0;
extern "C" void on_quit_signal(int) {
    quit_signal = 1;
}

enum class Screen { dashboard, control, signal, info, sky };
constexpr const char* kScreenNames[] = {"Dashboard", "Control", "Signal", "Info", "Sky"};
constexpr int kScreens = 5;
// What is up is asked again this often while the sky screen shows (each ask reads the TLEs).
constexpr double kSkyRefreshS = 30.0;
constexpr double kSteps[] = {0.1, 1.0, 5.0, 10.0};
constexpr int kMinColumns = 80, kMinLines = 24;

enum Colour : short { kGood = 1, kTarget, kBad, kAccent };

struct Prompt {
    enum class Purpose { none, go, scan, passes, track } purpose = Purpose::none;
    std::string label;
    std::string text;
};

struct Ui {
    Ui(tui::Station& station_, std::string skyscan_, std::string log_path_, tui::SkyOptions sky_)
        : station(station_),
          skyscan(std::move(skyscan_)),
          log_path(std::move(log_path_)),
          sky(std::move(sky_)),
          sky_clock(sky) {}
    tui::Station& station;
    std::string skyscan;
    std::string log_path;
    // The sky screen: birdcage-track's answers, as it gave them.
    tui::SkyOptions sky;
    tui::SkyClock sky_clock;
    tui::SkyQuery visible_query, passes_query;
    std::vector<tui::VisibleTarget> visible;
    std::string visible_time;
    std::optional<std::chrono::steady_clock::time_point> visible_asked;
    std::vector<tui::PassTimes> pass_list;
    std::string passes_of;  // the target the passes are of (as asked; then as birdcage-track names it)
    int selected = 0;
    tui::Tracker tracker;
    Screen screen = Screen::dashboard;
    int step_index = 1;
    Prompt prompt;
    std::string message;
    tui::ScanLauncher scan;
    std::string scan_file;
    bool colour = false;
    bool quit = false;
};

// ---- drawing helpers: every write is clipped to the window, so a small terminal never wraps -----

void put(int y, int x, const std::string& text, attr_t attributes = A_NORMAL) {
    if (y < 0 || y >= LINES || x < 0 || x >= COLS) {
        return;
    }
    // A control character would move the cursor: what a server sends is shown, never obeyed.
    std::string shown = text.substr(0, static_cast<std::size_t>(COLS - x));
    std::replace_if(
        shown.begin(), shown.end(), [](char c) { return static_cast<unsigned char>(c) < 32 || c == 127; }, ' ');
    attron(attributes);
    mvaddnstr(y, x, shown.c_str(), static_cast<int>(shown.size()));
    attroff(attributes);
}

void put_char(int y, int x, chtype c) {
    if (y >= 0 && y < LINES && x >= 0 && x < COLS) {
        mvaddch(y, x, c);
    }
}

attr_t colour(const Ui& ui, Colour c) {
    return ui.colour ? COLOR_PAIR(c) : A_NORMAL;
}

// `value` with `decimals` decimals, right-aligned in `width` columns.
std::string fixed(double value, int decimals, int width = 0) {
    char text[64];
    std::snprintf(text, sizeof text, "%*.*f", width, decimals, value);
    return text;
}

std::string degrees(double value) {
    return fixed(value, 2, 7);
}

std::string link_word(const tui::Snapshot& s) {
    switch (s.link) {
        case tui::LinkState::connected:
            return "connected";
        case tui::LinkState::connecting:
            return "connecting";
        case tui::LinkState::reconnecting:
            return "RECONNECTING";
    }
    return "?";
}

// Breaks text into lines of at most `width` characters at spaces.
std::vector<std::string> wrap(const std::string& text, int width) {
    std::vector<std::string> lines;
    std::istringstream words(text);
    std::string line;
    for (std::string w; words >> w;) {
        if (!line.empty() && static_cast<int>(line.size() + 1 + w.size()) > width) {
            lines.push_back(line);
            line.clear();
        }
        while (static_cast<int>(w.size()) > width) {
            lines.push_back(w.substr(0, static_cast<std::size_t>(width)));
            w.erase(0, static_cast<std::size_t>(width));
        }
        line += (line.empty() ? "" : " ") + w;
    }
    if (!line.empty())
        lines.push_back(line);
    return lines;
}

// ---- the compass rose and the elevation gauge ---------------------------------------------------

// A character cell is about twice as tall as wide: the rose is 2*r columns wide per r rows.
void draw_compass(const Ui& ui, const tui::Snapshot& s, int top, int left, int height, int width) {
    const int ry = std::max(2, std::min((height - 3) / 2, (width - 6) / 4));
    const int rx = 2 * ry;
    const int cy = top + height / 2, cx = left + width / 2;
    auto at = [&](double az_deg, double fraction, int& y, int& x) {
        const double a = az_deg * std::numbers::pi / 180.0;
        y = cy - static_cast<int>(std::lround(std::cos(a) * ry * fraction));
        x = cx + static_cast<int>(std::lround(std::sin(a) * rx * fraction));
    };
    // Dots every few degrees: about as many as the rim has cells, whatever the size.
    const int dot_step = std::max(1, 40 / ry);
    for (int deg = 0; deg < 360; deg += dot_step) {
        int y, x;
        at(deg, 1.0, y, x);
        put_char(y, x, '.');
    }
    for (int deg = 0; deg < 360; deg += 30) {
        int y, x;
        at(deg, 1.0, y, x);
        put_char(y, x, '+');
    }
    const char* labels[] = {"N", "E", "S", "W"};
    for (int i = 0; i < 4; ++i) {
        int y, x;
        at(i * 90.0, 1.0, y, x);
        y += i == 0 ? -1 : i == 2 ? 1 : 0;
        x += i == 1 ? 2 : i == 3 ? -2 : 0;
        put(y, x, labels[i], A_BOLD);
    }
    put_char(cy, cx, 'o');
    if (s.target) {
        int y, x;
        at(s.target->first, 1.0, y, x);
        put_char(y, x, 'X' | A_BOLD | colour(ui, kTarget));
    }
    if (s.position) {
        const double az = s.position->first;
        // The needle's character follows its slope, so it reads as a line at any angle.
        const double folded = std::fmod(std::fmod(az, 180.0) + 180.0, 180.0);
        const chtype stroke = folded < 22.5 || folded >= 157.5 ? '|'
                              : folded < 67.5                  ? '/'
                              : folded < 112.5                 ? '-'
                                                               : '\\';
        const int steps = rx * 2;
        int last_y = cy, last_x = cx;
        for (int i = 1; i <= steps; ++i) {
            int y, x;
            at(az, 0.85 * i / steps, y, x);
            if (y == last_y && x == last_x)
                continue;
            put_char(y, x, stroke | colour(ui, kGood));
            last_y = y;
            last_x = x;
        }
        put_char(last_y, last_x, '@' | A_BOLD | colour(ui, kGood));
    }
}

void draw_elevation_gauge(const Ui& ui, const tui::Snapshot& s, int top, int left, int height) {
    const int rows = std::max(3, height - 2);
    const double lo = std::min(0.0, s.limits.min_el), hi = std::max(90.0, s.limits.max_el);
    auto row_of = [&](double el) {
        const double f = std::clamp((el - lo) / (hi - lo), 0.0, 1.0);
        return top + 1 + static_cast<int>(std::lround((1.0 - f) * (rows - 1)));
    };
    put(top, left, "EL");
    for (int r = 0; r < rows; ++r) {
        put_char(top + 1 + r, left + 3, '|');
        put_char(top + 1 + r, left + 5, '|');
    }
    for (double mark : {0.0, 30.0, 60.0, 90.0}) {
        put(row_of(mark), left, fixed(mark, 0, 2));
    }
    if (s.position) {
        const int at = row_of(s.position->second);
        for (int r = at; r <= top + rows; ++r) {
            put_char(r, left + 4, '#' | colour(ui, kGood));
        }
    }
    if (s.target) {
        put_char(row_of(s.target->second), left + 6, '<' | A_BOLD | colour(ui, kTarget));
    }
}

// ---- screens ------------------------------------------------------------------------------------

// The numbers' column: the right 26 columns, the rose and gauge take the rest.
int panel_left() {
    return std::max(28, COLS - 26);
}

void draw_numbers(const Ui& ui, const tui::Snapshot& s, int& y, int x) {
    if (s.position) {
        put(y++, x, "Azimuth   " + degrees(s.position->first) + " deg", A_BOLD);
        put(y++, x, "Elevation " + degrees(s.position->second) + " deg", A_BOLD);
    } else {
        put(y++, x, "Azimuth      --.--");
        put(y++, x, "Elevation    --.--");
    }
    if (!s.position_error.empty()) {
        put(y++, x, "p: " + s.position_error, colour(ui, kBad));
    }
    if (s.target) {
        put(y++, x, "Target " + degrees(s.target->first) + degrees(s.target->second), colour(ui, kTarget));
    } else {
        put(y++, x, "Target     (none)");
    }
}

// The dashboard and the control screen share the pointing half: compass rose, elevation gauge
// and the numbers beside them. Returns the first free line of the right-hand panel.
int draw_pointing(const Ui& ui, const tui::Snapshot& s, int top, int height) {
    const int left_width = panel_left() - 10;
    draw_compass(ui, s, top, 0, height, left_width);
    draw_elevation_gauge(ui, s, top, left_width + 1, height);
    int y = top;
    draw_numbers(ui, s, y, panel_left());
    return y + 1;
}

void draw_dashboard(const Ui& ui, const tui::Snapshot& s, int top, int height) {
    const int x = panel_left();
    int y = draw_pointing(ui, s, top, height);
    put(y++, x, "Status  " + s.status.value_or("(not reported)"));
    put(y++, x, "Link    " + link_word(s), colour(ui, s.link == tui::LinkState::connected ? kGood : kBad));
    if (s.connects > 1) {
        put(y++, x, "        reconnected " + std::to_string(s.connects - 1) + "x");
    }
    ++y;
    put(y++, x, "Info (_):", A_BOLD);
    const int width = COLS - x - 1;
    for (const auto& line : wrap(s.info.empty() ? "(none)" : s.info, width)) {
        if (y >= top + height)
            break;
        put(y++, x, line);
    }
}

void draw_control(const Ui& ui, const tui::Snapshot& s, int top, int height) {
    const int x = panel_left();
    int y = draw_pointing(ui, s, top, height);
    put(y++, x, "Step    " + fixed(kSteps[ui.step_index], 1) + " deg", A_BOLD);
    ++y;
    put(y++, x, "Left/Right  azimuth -/+");
    put(y++, x, "Up/Down     elevation +/-");
    put(y++, x, "+ / -       step 0.1..10");
    put(y++, x, "g           go to AZ EL");
    put(y++, x, "s           stop");
    put(y++, x, std::string("k           park") + (s.caps.can_park ? "" : " (n/a)"));
    put(y++, x, std::string("h           home (R)") + (s.caps.can_reset ? "" : " (n/a)"));
    ++y;
    if (!s.busy.empty()) {
        put(y++, x, "busy: " + s.busy, colour(ui, kTarget));
    }
    for (const auto& line : wrap(s.last_result, COLS - x - 1)) {
        if (y >= top + height)
            break;
        put(y++, x, line);
    }
}

bool has_level(const tui::Snapshot& s, const char* name) {
    return std::find(s.levels.begin(), s.levels.end(), name) != s.levels.end();
}

// The sky-scan launcher: a process of its own, shown whatever the link does.
void draw_scan(const Ui& ui, int y) {
    put(y++, 1, "Sky scan (birdcage-skyscan)", A_BOLD);
    if (!ui.scan.started) {
        put(y++, 1, "n: scan a grid around the dish (its CSV goes to the current directory)");
        return;
    }
    if (ui.scan.total > 0) {
        const int w = std::max(10, COLS - 24);
        const int filled = ui.scan.done * w / ui.scan.total;
        put(y, 1,
            "[" + std::string(static_cast<std::size_t>(filled), '=') +
                std::string(static_cast<std::size_t>(w - filled), ' ') + "]");
        put(y, w + 4, std::to_string(ui.scan.done) + "/" + std::to_string(ui.scan.total));
        ++y;
    }
    put(y++, 1, ui.scan.outcome() + " -> " + ui.scan_file);
    put(y++, 1, ui.scan.progress);
}

void draw_signal(const Ui& ui, const tui::Snapshot& s, int top, int height) {
    int y = top;
    if (s.link != tui::LinkState::connected) {
        put(y++, 1, "not connected: no RSSI or LNB reading", A_BOLD);
        draw_scan(ui, y + 1);
        return;
    }
    if (!has_level(s, "RSSI")) {
        put(y++, 1, "This rotator lists no RSSI level (`v ?` answered: " +
                        (s.levels.empty() ? std::string("none") : [&] {
                            std::string all;
                            for (const auto& l : s.levels) all += (all.empty() ? "" : " ") + l;
                            return all;
                        }()) + ").");
        put(y++, 1, "The signal screen needs a receiver behind the rotator, such as the Carryout G2's tuner.");
        return;
    }
    if (!s.rssi && !s.signal_error.empty()) {
        put(y++, 1, "`v ?` lists RSSI, but `v RSSI` answers: " + s.signal_error, A_BOLD);
        put(y++, 1, "Of the Winegard dishes, only the Carryout G2 has a tuner the backend can read.");
        return;
    }
    const int bar_width = std::max(10, COLS - 30);
    double lo = 0, hi = 1;
    if (!s.rssi_trend.empty()) {
        lo = *std::min_element(s.rssi_trend.begin(), s.rssi_trend.end());
        hi = *std::max_element(s.rssi_trend.begin(), s.rssi_trend.end());
    }
    // The gauge starts at the noise floor (the weakest reading seen, rounded down) and ends at a
    // round number above the strongest: from 0, the floor alone would fill most of it.
    const double floor_level = s.rssi_trend.empty() ? 0.0 : std::floor(lo / 10.0) * 10.0;
    const double full = floor_level + std::max(10.0, std::ceil((hi - floor_level) * 1.2 / 10.0) * 10.0);
    std::string bar(static_cast<std::size_t>(bar_width), '.');
    if (s.rssi) {
        const double fraction = (*s.rssi - floor_level) / (full - floor_level);
        const int filled = static_cast<int>(std::lround(std::clamp(fraction, 0.0, 1.0) * bar_width));
        std::fill(bar.begin(), bar.begin() + filled, '#');
    }
    put(y, 1, "RSSI", A_BOLD);
    put(y, 6, s.rssi ? fixed(*s.rssi, 1, 7) : std::string("   ----"), A_BOLD);
    put(y, 14, "[" + bar + "]", colour(ui, kGood));
    put(y + 1, 14, fixed(floor_level, 0));
    put(y + 1, 14 + bar_width - 3, fixed(full, 0, 5));
    y += 2;
    put(y++, 1,
        "LNB  " +
            (s.lnb ? fixed(*s.lnb, 0) + " V" + (*s.lnb < 15 ? "  (13 V: vertical)" : "  (18 V: horizontal)")
                   : std::string("--")) +
            "    l toggles 13/18 V");
    if (s.position) {
        put(y++, 1, "Dish " + degrees(s.position->first) + degrees(s.position->second) + " (az el)");
    }
    ++y;
    // The trend: one column per reading, newest on the right, scaled to the readings shown.
    const int chart_rows = std::max(3, height - (y - top) - 6);
    const int chart_width = COLS - 10;
    const std::size_t shown = std::min<std::size_t>(s.rssi_trend.size(), static_cast<std::size_t>(chart_width));
    const double span = std::max(1.0, hi - lo);
    put(y, 1, fixed(hi, 0, 6));
    put(y + chart_rows - 1, 1, fixed(lo, 0, 6));
    for (int r = 0; r < chart_rows; ++r) {
        put_char(y + r, 8, '|');
    }
    for (std::size_t i = 0; i < shown; ++i) {
        const double v = s.rssi_trend[s.rssi_trend.size() - shown + i];
        const int level = static_cast<int>(std::lround((v - lo) / span * (chart_rows - 1)));
        const int col = 9 + chart_width - static_cast<int>(shown) + static_cast<int>(i);
        put_char(y + chart_rows - 1 - level, col, '*' | colour(ui, kAccent));
    }
    y += chart_rows + 1;
    draw_scan(ui, y);
}

std::vector<std::string> log_tail(const std::string& path, std::size_t count) {
    std::ifstream in(path);
    std::deque<std::string> lines;
    for (std::string line; std::getline(in, line);) {
        lines.push_back(line);
        if (lines.size() > count)
            lines.pop_front();
    }
    return {lines.begin(), lines.end()};
}

void draw_log(const Ui& ui, int y, int bottom) {
    if (ui.log_path.empty() || y >= bottom) {
        return;
    }
    put(y++, 1, "Log " + ui.log_path, A_BOLD);
    const auto lines = log_tail(ui.log_path, static_cast<std::size_t>(std::max(0, bottom - y)));
    if (lines.empty()) {
        put(y++, 1, "(not readable or empty)");
    }
    for (const auto& line : lines) {
        put(y++, 1, line);
    }
}

void draw_info(const Ui& ui, const tui::Snapshot& s, int top, int height) {
    int y = top;
    if (s.link != tui::LinkState::connected) {
        put(y++, 1, "not connected: the rotator's model, limits and info are read again when rotctld answers", A_BOLD);
        draw_log(ui, y + 1, top + height);
        return;
    }
    put(y++, 1, "Model    " + (s.caps.model.empty() ? std::string("?") : s.caps.model), A_BOLD);
    put(y++, 1, "Backend  " + s.caps.backend);
    put(y++, 1,
        "Can      " + std::string(s.caps.can_park ? "park " : "") + (s.caps.can_reset ? "home(R) " : "") +
            (s.caps.can_status ? "status " : "") + (s.levels.empty() ? "" : "levels"));
    put(y++, 1,
        "Limits   az " + fixed(s.limits.min_az, 2) + ".." + fixed(s.limits.max_az, 2) + "  el " +
            fixed(s.limits.min_el, 2) + ".." + fixed(s.limits.max_el, 2));
    // The Winegard backend's `_` is long (variant, limits, wrap, pointing, mapping): all of it.
    const int info_room =
        std::max(2, height - 7 - static_cast<int>(s.caps.levels.size()) - (ui.log_path.empty() ? 0 : 5));
    int info_lines = 0;
    for (const auto& line : wrap("Info (_) " + (s.info.empty() ? std::string("(none)") : s.info), COLS - 2)) {
        if (++info_lines > info_room)
            break;
        put(y++, 1, line);
    }
    ++y;
    // The backend's own description of its levels; its conf values in force are in `_` above
    // (Hamlib 4.5.4's rotctld has no `\get_conf`).
    if (!s.caps.levels.empty()) {
        put(y++, 1, "Extension levels (v/V)", A_BOLD);
        for (const auto& level : s.caps.levels) {
            std::string name = level.name;
            name.resize(std::max<std::size_t>(name.size(), 13), ' ');
            put(y++, 1, name + " " + level.label + (level.range.empty() ? "" : "  [" + level.range + "]"));
        }
        ++y;
    }
    draw_log(ui, y, top + height);
}

// ---- the sky screen: birdcage-track's answers (docs/sky.md), nothing computed here ---------------

// HH:MM:SS of an ISO time as birdcage-track prints it (UTC).
std::string clock_of(const std::string& iso) {
    return iso.size() >= 19 ? iso.substr(11, 8) : iso;
}

// "3m20s", "45s", "2h05m": how long until something, for a person.
std::string span_text(double seconds) {
    const long s = std::lround(std::max(0.0, seconds));
    char text[32];
    if (s >= 3600) {
        std::snprintf(text, sizeof text, "%ldh%02ldm", s / 3600, s % 3600 / 60);
    } else if (s >= 60) {
        std::snprintf(text, sizeof text, "%ldm%02lds", s / 60, s % 60);
    } else {
        std::snprintf(text, sizeof text, "%lds", s);
    }
    return text;
}

std::string az_el_text(const std::optional<std::pair<double, double>>& p) {
    return p ? "az " + fixed(p->first, 2, 6) + " el " + fixed(p->second, 2, 6) : std::string("--");
}

std::string selected_target(const Ui& ui) {
    if (!ui.visible.empty()) {
        return ui.visible[static_cast<std::size_t>(std::clamp(ui.selected, 0, static_cast<int>(ui.visible.size()) - 1))]
            .name;
    }
    return ui.passes_of;
}

void draw_track(const Ui& ui, int y, int x) {
    const tui::Tracker& t = ui.tracker;
    put(y++, x, "Track (t starts, x stops)", A_BOLD);
    if (!t.started()) {
        put(y++, x, "nothing tracked; t tracks the chosen target");
        return;
    }
    std::string state = t.target + ": " + t.phase;
    if (t.phase == "waiting" && t.seconds_to_aos) {
        state += ", AOS in " + span_text(*t.seconds_to_aos);
    } else if (t.phase == "tracking" && t.seconds_to_los) {
        state += ", LOS in " + span_text(*t.seconds_to_los);
    } else if (t.phase == "starting" && t.aos) {
        state += ", AOS " + clock_of(*t.aos);
    }
    put(y++, x, state, A_BOLD | colour(ui, t.running() ? kGood : kTarget));
    if (t.phase == "waiting") {
        put(y++, x, "waits at " + az_el_text(t.aim) + " for AOS" + (t.aos ? " " + clock_of(*t.aos) : ""));
    } else {
        put(y++, x, "target " + az_el_text(t.target_position), colour(ui, kTarget));
    }
    put(y++, x, "dish   " + az_el_text(t.dish_position), colour(ui, kGood));
    if (t.running()) {
        put(y++, x,
            "error " + (t.error_deg ? fixed(*t.error_deg, 2) + " deg" : std::string("--")) +
                (t.los ? "   LOS " + clock_of(*t.los) : "") + (t.max_el ? "  max el " + fixed(*t.max_el, 1) : ""));
        return;
    }
    std::string end = "ended: " + t.phase;
    if (t.rms_error_deg) {
        end += ", rms " + fixed(*t.rms_error_deg, 2) + " max " + fixed(t.max_error_deg.value_or(NAN), 2) + " deg, " +
               std::to_string(t.samples) + " samples";
    }
    if (t.stopped && t.phase == "interrupted") {
        end += " (x/s)";
    }
    put(y++, x, end);
    put(y++, x, t.reason);
}

void draw_sky(const Ui& ui, const tui::Snapshot& s, int top, int height) {
    const int x = 1;
    const int rose_width = 32, left_width = COLS - rose_width - 2;
    int y = top;
    // What is up now, from --visible: in the window first, then the highest.
    std::string head = "Up now";
    if (!ui.visible_time.empty()) {
        head += " (" + clock_of(ui.visible_time) + " UTC)";
    }
    put(y, x, head, A_BOLD);
    put(y, x + static_cast<int>(head.size()) + 2,
        ui.visible_query.running() ? "asking birdcage-track..." : "* in the dish's window; r refreshes");
    ++y;
    constexpr int kRows = 7;
    if (ui.visible.empty()) {
        put(y, x + 2, ui.visible_asked ? "nothing above the dish's floor" : "r asks birdcage-track what is up");
    }
    const int count = static_cast<int>(ui.visible.size());
    const int first = std::clamp(ui.selected - kRows + 1, 0, std::max(0, count - kRows));
    for (int i = first; i < std::min(count, first + kRows); ++i) {
        const auto& t = ui.visible[static_cast<std::size_t>(i)];
        std::string name = t.name.substr(0, 18);
        name.resize(18, ' ');
        std::string kind = t.kind.substr(0, 9);
        kind.resize(9, ' ');
        const bool chosen = i == ui.selected;
        put(y + i - first, x,
            std::string(chosen ? "> " : "  ") + name + " " + kind + " az " + fixed(t.az, 1, 5) + " el " +
                fixed(t.el, 1, 4) + (t.in_window ? " *" : ""),
            chosen ? A_BOLD : A_NORMAL);
    }
    y += kRows + 1;
    // The chosen target's passes through the dish's window, from --passes.
    put(y++, x,
        "Passes of " + (ui.passes_of.empty() ? std::string("(p asks for the chosen target)") : ui.passes_of) +
            (ui.passes_query.running() ? "  asking..." : ""),
        A_BOLD);
    if (!ui.pass_list.empty()) {
        put(y++, x, "  AOS       LOS       max el  az         AOS in");
        for (std::size_t i = 0; i < std::min<std::size_t>(ui.pass_list.size(), 3); ++i) {
            const auto& p = ui.pass_list[i];
            const auto aos = tui::parse_iso_time(p.aos);
            const double to_aos = aos ? *aos - ui.sky_clock.now() : std::nan("");
            put(y++, x,
                "  " + clock_of(p.aos) + "  " + clock_of(p.los) + "  " + fixed(p.max_el, 1, 6) + "  " +
                    fixed(p.aos_az, 0, 3) + "->" + fixed(p.los_az, 0, 3) + "  " +
                    (std::isnan(to_aos) ? std::string("?")
                     : to_aos <= 0      ? std::string("now")
                                        : span_text(to_aos)));
        }
    } else if (!ui.passes_of.empty() && !ui.passes_query.running()) {
        put(y++, x, "  no pass through the dish's window in the next 24 h");
    }
    // The track's six lines at the bottom (the passes above end by then at 80x24).
    draw_track(ui, std::max(y, top + height - 6), x);
    // The target against the dish: the rose with the dish's needle (@) and the target (X).
    tui::Snapshot view = s;
    view.target = ui.tracker.target_position      ? ui.tracker.target_position
                  : ui.tracker.phase == "waiting" ? ui.tracker.aim
                                                  : std::nullopt;
    if (!ui.tracker.running()) {
        view.target.reset();
    }
    draw_compass(ui, view, top, left_width + 2, std::min(height, 15), rose_width);
    put(top + std::min(height, 15), left_width + 4, "@ dish  X target", A_NORMAL);
}

void draw(Ui& ui, const tui::Snapshot& s) {
    erase();
    // Below 80x24 the screens overlap and the key bar is cut: say so, as cgps does, and keep going
    // (q still quits; a larger window brings the screens back).
    if (COLS < kMinColumns || LINES < kMinLines) {
        put(0, 0,
            "terminal too small (need " + std::to_string(kMinColumns) + "x" + std::to_string(kMinLines) + ", have " +
                std::to_string(COLS) + "x" + std::to_string(LINES) + ")",
            A_BOLD);
        put(1, 0, "enlarge it, or q to quit");
        curs_set(0);
        refresh();
        return;
    }
    // Row 0: who and how the link is; row 1: the screens.
    const bool up = s.link == tui::LinkState::connected;
    std::string title = " birdcage-tui  rotctld " + ui.station.address() + "  link: " + link_word(s);
    title.resize(static_cast<std::size_t>(std::max(COLS, 0)), ' ');
    put(0, 0, title, A_REVERSE | (up ? A_NORMAL : A_BOLD));
    int x = 1;
    for (int i = 0; i < kScreens; ++i) {
        const bool current = static_cast<int>(ui.screen) == i;
        const std::string tab =
            (current ? "[" : " ") + std::to_string(i + 1) + " " + kScreenNames[i] + (current ? "]" : " ");
        put(1, x, tab, current ? A_BOLD : A_NORMAL);
        x += static_cast<int>(tab.size()) + 1;
    }
    const int top = 2, height = LINES - 4;
    if (!up && s.link_detail.size() > 0) {
        put(top, 1, s.link_detail, A_BOLD | colour(ui, kBad));
    }
    const int body_top = up ? top : top + 1, body_height = up ? height : height - 1;
    switch (ui.screen) {
        case Screen::dashboard:
            draw_dashboard(ui, s, body_top, body_height);
            break;
        case Screen::control:
            draw_control(ui, s, body_top, body_height);
            break;
        case Screen::signal:
            draw_signal(ui, s, body_top, body_height);
            break;
        case Screen::info:
            draw_info(ui, s, body_top, body_height);
            break;
        case Screen::sky:
            draw_sky(ui, s, body_top, body_height);
            break;
    }
    // Row LINES-2: the prompt or the last message; row LINES-1: the keys.
    if (ui.prompt.purpose != Prompt::Purpose::none) {
        put(LINES - 2, 0, ui.prompt.label + ui.prompt.text, A_BOLD);
        move(LINES - 2, std::min(COLS - 1, static_cast<int>(ui.prompt.label.size() + ui.prompt.text.size())));
        curs_set(1);
    } else {
        std::string line = !ui.message.empty()            ? ui.message
                           : !s.busy.empty()              ? "busy: " + s.busy
                           : !s.last_result.empty() || up ? s.last_result
                                                          : "not connected";
        put(LINES - 2, 0, line);
        curs_set(0);
    }
    std::string keys = "1-5/Tab screens  arrows jog  +/- step  g goto  s stop  k park  h home  q quit";
    if (ui.screen == Screen::signal) {
        keys = "1-5/Tab screens  l LNB 13/18  n sky scan  x stop scan  g goto  s stop  q quit";
    } else if (ui.screen == Screen::sky) {
        keys = "1-5/Tab screens  [ ] choose  p passes  t track  x stop track  r refresh  q quit";
    }
    put(LINES - 1, 0, keys, A_REVERSE);
    refresh();
}

// ---- keys ---------------------------------------------------------------------------------------

// A command that moves the dish must not fight a running track: refused, with how to end the track.
bool refused_while_tracking(Ui& ui, const std::string& what) {
    if (!ui.tracker.running()) {
        return false;
    }
    ui.message = what + " refused: tracking " + ui.tracker.target + " (x on the sky screen, or s, ends it)";
    return true;
}

void ask_visible(Ui& ui) {
    ui.visible_asked = std::chrono::steady_clock::now();
    if (ui.visible_query.running()) {
        return;
    }
    auto args = tui::sky_common_args(ui.sky, ui.sky_clock);
    args.push_back("--visible");
    std::string why;
    if (!ui.visible_query.start(ui.sky.program, args, &why)) {
        ui.message = why;
    }
}

void ask_passes(Ui& ui, const std::string& target) {
    if (target.empty()) {
        ui.message = "type a target: a satellite, sun, moon, a planet";
        return;
    }
    if (ui.passes_query.running()) {
        ui.message = "still asking for the passes of " + ui.passes_of;
        return;
    }
    auto args = tui::sky_common_args(ui.sky, ui.sky_clock);
    args.insert(args.end(), {"--passes", "--hours", "24", "--count", "3", target});
    ui.passes_of = target;
    ui.pass_list.clear();
    std::string why;
    if (!ui.passes_query.start(ui.sky.program, args, &why)) {
        ui.message = why;
    }
}

void start_track(Ui& ui, const tui::Snapshot& s, const std::string& target) {
    if (target.empty()) {
        ui.message = "type a target: a satellite, sun, moon, a planet";
        return;
    }
    if (s.link != tui::LinkState::connected) {
        ui.message = "not connected: rotctld at " + ui.station.address() + " is not answering";
        return;
    }
    if (ui.scan.running()) {
        ui.message = "a sky scan is running (x on the signal screen stops it)";
        return;
    }
    std::string why;
    if (!ui.tracker.start(ui.sky.program, tui::sky_common_args(ui.sky, ui.sky_clock), target, &why)) {
        ui.message = why;
        return;
    }
    ui.message = "started: birdcage-track --json " + target;
}

// Reads what the sky programs printed since the last frame; asks what is up again while the sky
// screen shows.
void pump_sky(Ui& ui) {
    ui.tracker.pump();
    if (ui.visible_query.pump()) {
        if (ui.visible_query.answer) {
            ui.visible = tui::visible_targets(*ui.visible_query.answer);
            ui.visible_time = ui.visible_query.answer->text_at("time");
            ui.selected = std::clamp(ui.selected, 0, std::max(0, static_cast<int>(ui.visible.size()) - 1));
        } else {
            ui.message = "birdcage-track --visible: " + ui.visible_query.error;
        }
    }
    if (ui.passes_query.pump()) {
        if (ui.passes_query.answer) {
            ui.pass_list = tui::passes(*ui.passes_query.answer);
            ui.passes_of = ui.passes_query.answer->text_at("target", ui.passes_of);
        } else {
            ui.message = "birdcage-track --passes: " + ui.passes_query.error;
        }
    }
    const auto now = std::chrono::steady_clock::now();
    if (ui.screen == Screen::sky &&
        (!ui.visible_asked || std::chrono::duration<double>(now - *ui.visible_asked).count() > kSkyRefreshS)) {
        ask_visible(ui);
    }
}

void jog(Ui& ui, double daz, double del) {
    if (refused_while_tracking(ui, "jog")) {
        return;
    }
    // The station takes the dish's position when the jog runs (a fresh `p`), not from this screen.
    ui.station.submit({tui::Command::Kind::jog, daz, del, {}});
    ui.message.clear();
}

void submit_go(Ui& ui, const tui::Snapshot& s, const std::string& text) {
    std::string cleaned = text;
    std::replace(cleaned.begin(), cleaned.end(), ',', ' ');
    std::istringstream in(cleaned);
    double az = 0, el = 0;
    std::string rest;
    if (!(in >> az >> el) || (in >> rest) || !std::isfinite(az) || !std::isfinite(el)) {
        ui.message = "type AZ EL in degrees, e.g. 200 35";
        return;
    }
    if (refused_while_tracking(ui, "g")) {
        return;
    }
    // The rotator's own range, as rotctld announces it: outside it nothing is sent, nothing clamped.
    if (const std::string why = tui::out_of_range(s.limits, az, el); !why.empty()) {
        ui.message = "refused: " + why;
        return;
    }
    ui.station.submit({tui::Command::Kind::move, az, el, {}});
    ui.message.clear();
}

void submit_scan(Ui& ui, const std::string& text) {
    std::istringstream in(text);
    std::string az, el, lnb;
    if (!(in >> az >> el)) {
        ui.message = "type AZ_FROM:AZ_TO:STEP EL_FROM:EL_TO:STEP [13|18]";
        return;
    }
    in >> lnb;
    char name[64];
    const std::time_t now = std::time(nullptr);
    std::tm tm{};
    localtime_r(&now, &tm);
    std::strftime(name, sizeof name, "skyscan-%Y%m%d-%H%M%S.csv", &tm);
    ui.scan_file = name;
    const auto colon = ui.station.address().rfind(':');
    std::string host = ui.station.address().substr(0, colon);
    if (host.size() > 2 && host.front() == '[')
        host = host.substr(1, host.size() - 2);
    std::vector<std::string> args{"--host", host,        "--port", ui.station.address().substr(colon + 1),
                                  "--az",   az,          "--el",   el,
                                  "--out",  ui.scan_file};
    if (!lnb.empty()) {
        args.insert(args.end(), {"--lnb", lnb});
    }
    std::string why;
    if (!ui.scan.start(ui.skyscan, args, &why)) {
        ui.message = why;
        return;
    }
    ui.message = "started: birdcage-skyscan --az " + az + " --el " + el + (lnb.empty() ? "" : " --lnb " + lnb);
}

void open_scan_prompt(Ui& ui, const tui::Snapshot& s) {
    if (refused_while_tracking(ui, "a sky scan")) {
        return;
    }
    if (ui.scan.running()) {
        ui.message = "a scan is running (x stops it)";
        return;
    }
    // A small grid around where the dish points: a quick look, not the whole sky.
    const double az = s.position ? std::round(s.position->first) : 180.0;
    const double el = s.position ? std::round(s.position->second) : 30.0;
    const double el_lo = std::max(s.limits.min_el, el - 6), el_hi = std::min(s.limits.max_el, el + 6);
    char text[96];
    std::snprintf(text, sizeof text, "%.0f:%.0f:2 %.0f:%.0f:2", std::max(s.limits.min_az, az - 10),
                  std::min(s.limits.max_az, az + 10), std::ceil(el_lo), std::floor(el_hi));
    ui.prompt = {Prompt::Purpose::scan, "Scan AZ FROM:TO:STEP EL FROM:TO:STEP [LNB]: ", text};
}

void prompt_key(Ui& ui, const tui::Snapshot& s, int key) {
    if (key == 27) {
        ui.prompt = {};
        ui.message = "cancelled";
    } else if (key == '\n' || key == '\r' || key == KEY_ENTER) {
        const Prompt done = ui.prompt;
        ui.prompt = {};
        if (done.purpose == Prompt::Purpose::go && s.link != tui::LinkState::connected) {
            ui.message = "not connected: rotctld at " + ui.station.address() + " is not answering";
        } else if (done.purpose == Prompt::Purpose::go) {
            submit_go(ui, s, done.text);
        }
        if (done.purpose == Prompt::Purpose::scan)
            submit_scan(ui, done.text);
        if (done.purpose == Prompt::Purpose::passes)
            ask_passes(ui, done.text);
        if (done.purpose == Prompt::Purpose::track)
            start_track(ui, s, done.text);
    } else if (key == KEY_BACKSPACE || key == 127 || key == 8) {
        if (!ui.prompt.text.empty())
            ui.prompt.text.pop_back();
    } else if (key == 21) {  // ^U, as in a shell
        ui.prompt.text.clear();
    } else if (key >= 32 && key < 127 && ui.prompt.text.size() < 60) {
        ui.prompt.text.push_back(static_cast<char>(key));
    }
}

void key(Ui& ui, const tui::Snapshot& s, int key) {
    if (ui.prompt.purpose != Prompt::Purpose::none) {
        prompt_key(ui, s, key);
        return;
    }
    const double step = kSteps[ui.step_index];
    // A stop ends a track too, whatever the link does: birdcage-track sends `S` as it ends.
    if ((key == 's' || key == 'S' || key == ' ') && ui.tracker.running()) {
        ui.tracker.cancel();
        ui.message = "tracking of " + ui.tracker.target + " stopped";
        if (s.link == tui::LinkState::connected) {
            ui.station.submit({tui::Command::Kind::stop, 0, 0, {}});
        }
        return;
    }
    // Disconnected, every key that would talk to the rotator says so instead of doing nothing.
    static const std::string kTalks = "gGsS kKhHlLnNtT";
    const bool talks = (key > 0 && key < 128 && kTalks.find(static_cast<char>(key)) != std::string::npos) ||
                       key == KEY_LEFT || key == KEY_RIGHT || key == KEY_UP || key == KEY_DOWN;
    if (talks && s.link != tui::LinkState::connected) {
        ui.message = "not connected: rotctld at " + ui.station.address() + " is not answering";
        return;
    }
    switch (key) {
        case 'q':
        case 'Q':
            ui.quit = true;
            break;
        case '1':
        case '2':
        case '3':
        case '4':
        case '5':
            ui.screen = static_cast<Screen>(key - '1');
            ui.message.clear();
            break;
        case '\t':
            ui.screen = static_cast<Screen>((static_cast<int>(ui.screen) + 1) % kScreens);
            ui.message.clear();
            break;
        case KEY_BTAB:
            ui.screen = static_cast<Screen>((static_cast<int>(ui.screen) + kScreens - 1) % kScreens);
            ui.message.clear();
            break;
        case KEY_LEFT:
            jog(ui, -step, 0);
            break;
        case KEY_RIGHT:
            jog(ui, step, 0);
            break;
        case KEY_UP:
            jog(ui, 0, step);
            break;
        case KEY_DOWN:
            jog(ui, 0, -step);
            break;
        case '+':
        case '=':
            ui.step_index = std::min(ui.step_index + 1, 3);
            ui.message = "step " + fixed(kSteps[ui.step_index], 1) + " deg";
            break;
        case '-':
        case '_':
            ui.step_index = std::max(ui.step_index - 1, 0);
            ui.message = "step " + fixed(kSteps[ui.step_index], 1) + " deg";
            break;
        case 'g':
        case 'G':
            ui.prompt = {Prompt::Purpose::go, "Go to AZ EL: ", ""};
            break;
        case 's':
        case 'S':
        case ' ':
            ui.station.submit({tui::Command::Kind::stop, 0, 0, {}});
            ui.message.clear();
            break;
        case 'k':
        case 'K':
            if (refused_while_tracking(ui, "park"))
                break;
            if (s.caps.can_park)
                ui.station.submit({tui::Command::Kind::park, 0, 0, {}});
            ui.message = s.caps.can_park ? "" : "this rotator cannot park";
            break;
        case 'h':
        case 'H':
            if (refused_while_tracking(ui, "home"))
                break;
            if (s.caps.can_reset)
                ui.station.submit({tui::Command::Kind::home, 0, 0, {}});
            ui.message = s.caps.can_reset ? "" : "this rotator cannot home (no R)";
            break;
        case 'l':
        case 'L':
            if (ui.screen != Screen::signal)
                break;
            if (!has_level(s, "LNB")) {
                ui.message = "this rotator has no LNB level";
            } else {
                ui.station.submit({tui::Command::Kind::set_level, s.lnb && *s.lnb < 15 ? 18.0 : 13.0, 0, "LNB"});
                ui.message.clear();
            }
            break;
        case 'n':
        case 'N':
            if (ui.screen != Screen::signal)
                break;
            if (!has_level(s, "RSSI") || (!s.rssi && !s.signal_error.empty()))
                ui.message = "this rotator has no RSSI to scan with";
            else
                open_scan_prompt(ui, s);
            break;
        case 'x':
        case 'X':
            if (ui.screen == Screen::signal && ui.scan.running()) {
                ui.scan.cancel();
                ui.message = "scan stopped; birdcage-skyscan --resume continues it";
            } else if (ui.screen == Screen::sky && ui.tracker.running()) {
                ui.tracker.cancel();
                ui.message = "tracking of " + ui.tracker.target + " stopped";
            }
            break;
        case '[':
        case ']':
            if (ui.screen == Screen::sky && !ui.visible.empty()) {
                const int count = static_cast<int>(ui.visible.size());
                ui.selected = (ui.selected + (key == ']' ? 1 : count - 1)) % count;
            }
            break;
        case 'p':
        case 'P':
            if (ui.screen == Screen::sky)
                ui.prompt = {Prompt::Purpose::passes, "Passes of: ", selected_target(ui)};
            break;
        case 't':
        case 'T':
            if (ui.screen != Screen::sky)
                break;
            if (ui.tracker.running())
                ui.message = "already tracking " + ui.tracker.target + " (x stops it)";
            else
                ui.prompt = {Prompt::Purpose::track, "Track: ", selected_target(ui)};
            break;
        case 'r':
        case 'R':
            if (ui.screen == Screen::sky) {
                ask_visible(ui);
                if (!ui.passes_of.empty())
                    ask_passes(ui, ui.passes_of);
            }
            break;
        case KEY_RESIZE:
            clearok(stdscr, TRUE);
            break;
        default:
            break;
    }
}

void start_colour(Ui& ui) {
    if (!has_colors()) {
        return;
    }
    start_color();
    use_default_colors();
    init_pair(kGood, COLOR_GREEN, -1);
    init_pair(kTarget, COLOR_YELLOW, -1);
    init_pair(kBad, COLOR_RED, -1);
    init_pair(kAccent, COLOR_CYAN, -1);
    ui.colour = true;
}

}  // namespace

int main(int argc, char** argv) {
    std::string host = "localhost", log_path, track_program;
    int port = 4533;
    tui::SkyOptions sky;
    birdcage::cli::ArgCursor args(argc, argv);
    while (args.next()) {
        const std::string& arg = args.flag();
        const bool inline_value = args.has_inline_value();
        auto value = [&] { return args.value(); };
        if ((arg == "--help" || arg == "-h") && !inline_value) {
            std::cout << usage_text;
            return 0;
        } else if (arg == "--version" && !inline_value) {
            std::cout << "birdcage-tui " BIRDCAGE_VERSION "\n";
            return 0;
        } else if (arg == "--help" || arg == "--version") {
            return usage_error(arg + " takes no value");
        } else if (arg == "--host" || arg == "--log") {
            const auto v = value();
            if (!v || v->empty())
                return usage_error(arg + " needs a value");
            (arg == "--host" ? host : log_path) = *v;
        } else if (arg == "--track-program" || arg == "--tle") {
            const auto v = value();
            if (!v || v->empty())
                return usage_error(arg + " needs a value");
            if (arg == "--tle")
                sky.tles.push_back(*v);
            else
                track_program = *v;
        } else if (arg == "--lat" || arg == "--lon" || arg == "--alt" || arg == "--time-scale") {
            const auto v = value();
            char* end = nullptr;
            const double n = v ? std::strtod(v->c_str(), &end) : std::nan("");
            if (!v || v->empty() || *end != '\0' || !std::isfinite(n) || (arg == "--time-scale" && n <= 0))
                return usage_error(arg + (arg == "--time-scale" ? " needs a number above 0" : " needs a number"));
            (arg == "--lat" ? sky.lat : arg == "--lon" ? sky.lon : arg == "--alt" ? sky.alt : sky.time_scale) = n;
        } else if (arg == "--at") {
            const auto v = value();
            const auto at = v ? tui::parse_iso_time(*v) : std::nullopt;
            if (!at)
                return usage_error("--at needs an ISO 8601 UTC time, e.g. 2026-12-01T12:00:00Z");
            sky.at = *at;
        } else if (arg == "--port") {
            const auto v = value();
            char* end = nullptr;
            const long n = v ? std::strtol(v->c_str(), &end, 10) : 0;
            if (!v || v->empty() || *end != '\0' || n < 1 || n > 65535)
                return usage_error("--port needs a number 1..65535");
            port = static_cast<int>(n);
        } else {
            return usage_error("unknown argument '" + arg + "'");
        }
    }

    std::signal(SIGPIPE, SIG_IGN);  // a write to a rotctld that just went away must not kill us
    struct sigaction quit_action {};
    quit_action.sa_handler = on_quit_signal;
    sigaction(SIGINT, &quit_action, nullptr);
    sigaction(SIGTERM, &quit_action, nullptr);
    sigaction(SIGHUP, &quit_action, nullptr);

    if (!isatty(STDIN_FILENO) || !isatty(STDOUT_FILENO)) {
        std::cerr << "birdcage-tui: needs a terminal (for scripts: rotctl -m 2 -r " << host << ":" << port << ")\n";
        return 1;
    }
    SCREEN* terminal = newterm(nullptr, stdout, stdin);
    if (terminal == nullptr) {
        std::cerr << "birdcage-tui: cannot drive this terminal (TERM="
                  << (std::getenv("TERM") ? std::getenv("TERM") : "") << ")\n";
        return 1;
    }
    cbreak();
    noecho();
    keypad(stdscr, TRUE);
    set_escdelay(25);
    timeout(100);
    curs_set(0);

    {
        tui::Station station(host, port);
        sky.host = host;
        sky.port = port;
        sky.program = track_program.empty() ? tui::tool_program(argv[0], "birdcage-track", "tools/sky") : track_program;
        Ui ui(station, tui::skyscan_program(argv[0]), log_path, sky);
        start_colour(ui);
        while (!ui.quit && quit_signal == 0) {
            station.watch_signal(ui.screen == Screen::signal);
            ui.scan.pump();
            pump_sky(ui);
            const tui::Snapshot s = station.snapshot();
            draw(ui, s);
            const int k = getch();
            if (k != ERR) {
                key(ui, s, k);
            }
        }
        // A track does not outlive the screen that shows it: birdcage-track sends `S` as it ends.
        ui.tracker.cancel();
        ui.visible_query.cancel();
        ui.passes_query.cancel();
        endwin();
    }
    delscreen(terminal);
    return 0;
}
