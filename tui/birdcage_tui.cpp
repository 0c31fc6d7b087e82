// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage-tui: a terminal dashboard and control panel for any rotator behind rotctld, with the
// Winegard extras (signal, LNB, homing, variant) where the backend offers them. A client of
// rotctld, so it runs beside Gpredict. docs/tui.md shows the screens.
#include "birdcage_version.hpp"
#include "cli_args.hpp"
#include "scan_launcher.hpp"
#include "station.hpp"

#include <curses.h>

#include <unistd.h>
#include <algorithm>
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

const char* const usage_text = R"(Usage: birdcage-tui [--host H] [--port P] [--log FILE]

A terminal UI for a rotator behind rotctld (any Hamlib rotator; the Winegard dish's signal, LNB,
homing and variant where the birdcage backend offers them). It is one more rotctld client, so it
runs beside Gpredict or any other. It reconnects by itself when rotctld restarts.

  --host H      rotctld's host (default localhost)
  --port P      rotctld's TCP port (default 4533)
  --log FILE    show the tail of this file on the info screen (e.g. rotctld's log)
  --help        this text
  --version     the program's version

Screens: 1 dashboard, 2 control, 3 signal, 4 info (Tab cycles).
Keys on every screen: arrows jog by the step, +/- choose the step (0.1, 1, 5, 10 deg),
g go to AZ EL, s stop, k park, h home (R, where the rotator can), q quit.
Signal screen: l toggles the LNB supply 13/18 V, n starts a sky scan (birdcage-skyscan), x stops it.
)";

int usage_error(const std::string& message) {
    std::cerr << "birdcage-tui: " << message << " (see --help)\n";
    return 2;
}

volatile std::sig_atomic_t quit_signal = 0;
extern "C" void on_quit_signal(int) {
    quit_signal = 1;
}

enum class Screen { dashboard, control, signal, info };
constexpr const char* kScreenNames[] = {"Dashboard", "Control", "Signal", "Info"};
constexpr double kSteps[] = {0.1, 1.0, 5.0, 10.0};
constexpr int kMinColumns = 80, kMinLines = 24;

enum Colour : short { kGood = 1, kTarget, kBad, kAccent };

struct Prompt {
    enum class Purpose { none, go, scan } purpose = Purpose::none;
    std::string label;
    std::string text;
};

struct Ui {
    Ui(tui::Station& station_, std::string skyscan_, std::string log_path_)
        : station(station_), skyscan(std::move(skyscan_)), log_path(std::move(log_path_)) {}
    tui::Station& station;
    std::string skyscan;
    std::string log_path;
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
    for (int i = 0; i < 4; ++i) {
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
    std::string keys = "1-4/Tab screens  arrows jog  +/- step  g goto  s stop  k park  h home  q quit";
    if (ui.screen == Screen::signal) {
        keys = "1-4/Tab screens  l LNB 13/18  n sky scan  x stop scan  g goto  s stop  q quit";
    }
    put(LINES - 1, 0, keys, A_REVERSE);
    refresh();
}

// ---- keys ---------------------------------------------------------------------------------------

void jog(Ui& ui, double daz, double del) {
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
    // Disconnected, every key that would talk to the rotator says so instead of doing nothing.
    static const std::string kTalks = "gGsS kKhHlLnN";
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
            ui.screen = static_cast<Screen>(key - '1');
            ui.message.clear();
            break;
        case '\t':
            ui.screen = static_cast<Screen>((static_cast<int>(ui.screen) + 1) % 4);
            ui.message.clear();
            break;
        case KEY_BTAB:
            ui.screen = static_cast<Screen>((static_cast<int>(ui.screen) + 3) % 4);
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
            if (s.caps.can_park)
                ui.station.submit({tui::Command::Kind::park, 0, 0, {}});
            ui.message = s.caps.can_park ? "" : "this rotator cannot park";
            break;
        case 'h':
        case 'H':
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
    std::string host = "localhost", log_path;
    int port = 4533;
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
        Ui ui(station, tui::skyscan_program(argv[0]), log_path);
        start_colour(ui);
        while (!ui.quit && quit_signal == 0) {
            station.watch_signal(ui.screen == Screen::signal);
            ui.scan.pump();
            const tui::Snapshot s = station.snapshot();
            draw(ui, s);
            const int k = getch();
            if (k != ERR) {
                key(ui, s, k);
            }
        }
        endwin();
    }
    delscreen(terminal);
    return 0;
}
