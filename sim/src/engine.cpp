// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The emulated console's engine (engine.hpp): line intake, the shell's common verbs (help, quit,
// unknown command), and the timed behaviours every variant shares (boot, the TV-satellite search,
// busy moves, stalls, idle lines). Just over 500 lines because each of those is a short state
// machine driven by the same tick(); the per-variant menus live in variants.cpp and handlers.cpp.
#include "engine.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <utility>

#include "firmware/hazards.hpp"

namespace birdcage::sim {
namespace {

// What the known clients legitimately ask of a console (docs/firmware.md §15): well-formed moves and
// homes, the documented search stops and the LNB switch. Any other word the core's hazard rule
// names counts as a hazard, however the emulated firmware answers it.
constexpr birdcage::HazardRequests client_requests =
    birdcage::request_move | birdcage::request_home | birdcage::request_search_stop | birdcage::request_lnb_supply;

birdcage::VariantId core_variant(Variant variant) {
    switch (variant) {
        case Variant::travler_hal000:
            return birdcage::VariantId::travler_hal000;
        case Variant::travler_hal205:
            return birdcage::VariantId::travler_hal205;
        case Variant::travler_pro:
            return birdcage::VariantId::travler_pro;
        case Variant::carryout2003:
            return birdcage::VariantId::carryout2003;
        case Variant::carryout_g2:
            return birdcage::VariantId::carryout_g2;
    }
    return birdcage::VariantId::carryout_g2;
}

// The core's name of a menu: "root" for a shell root, "eeprom" for the G2's EE>, otherwise the
// prompt's word in lower case (as the backend's session names them).
std::string core_menu_name(const Menu& menu) {
    if (menu.shell_root)
        return "root";
    if (menu.prompt_name == "EE")
        return "eeprom";
    std::string name(menu.prompt_name);
    for (char& c : name)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return name;
}

constexpr double max_tick = 0.02;     // simulated seconds per event step
constexpr double truth_period = 0.1;  // simulated seconds between truth rows
constexpr double search_dwell = 0.5;  // INVENTED pause between search moves

AxisParams with_dynamics(AxisParams axis, std::optional<double> velocity, const MotorDynamics& motor) {
    if (velocity)
        axis.max_velocity = *velocity;
    if (motor.accel)
        axis.max_accel = *motor.accel;
    axis.startup_delay = motor.startup_delay;
    return axis;
}

double initial_mechanical_az(const VariantProfile& profile, double start_az) {
    if (start_az >= profile.az.min && start_az <= profile.az.max)
        return start_az;
    return nearest_wrap_branch(start_az, 0.0, profile.az.min, profile.az.max);
}

std::vector<std::string_view> split_words(std::string_view line) {
    std::vector<std::string_view> words;
    std::size_t pos = 0;
    while (pos < line.size()) {
        while (pos < line.size() && (line[pos] == ' ' || line[pos] == '\t'))
            ++pos;
        const std::size_t start = pos;
        while (pos < line.size() && line[pos] != ' ' && line[pos] != '\t')
            ++pos;
        if (pos > start)
            words.push_back(line.substr(start, pos - start));
    }
    return words;
}

// The documented boot steps with the dialect's extra lines and silences inserted before the
// documented line they name; those after the last one follow the completion marker, where input is
// already kept (a client may answer the marker at once, §3.6).
std::vector<BootStep> with_extra_boot_lines(std::vector<BootStep> documented,
                                            const std::vector<ExtraBootLine>& extras) {
    if (extras.empty())
        return documented;
    using K = BootStep::Kind;
    const auto documented_lines = static_cast<std::size_t>(
        std::count_if(documented.begin(), documented.end(), [](const BootStep& step) { return step.kind == K::line; }));
    std::vector<BootStep> steps;
    auto append_extras = [&](auto belongs) {
        for (const ExtraBootLine& extra : extras) {
            if (!belongs(extra.before_documented))
                continue;
            if (extra.silence_before > 0.0)
                steps.push_back({K::pause, "", 0, 0.0, extra.silence_before});
            if (!extra.text.empty())
                steps.push_back({K::line, extra.text});
        }
    };
    // Index 0 is the power-on banner, before anything the documented boot does (moves included);
    // on a silent boot every extra goes there.
    append_extras([&](std::size_t index) { return index == 0 || documented_lines == 0; });
    std::size_t line_index = 0;
    bool ready_seen = false;
    for (BootStep& step : documented) {
        if (step.kind == K::line && line_index++ > 0) {
            append_extras([&](std::size_t index) { return index == line_index - 1; });
        }
        ready_seen = ready_seen || step.kind == K::ready;
        steps.push_back(std::move(step));
    }
    if (documented_lines == 0)
        return steps;
    if (!ready_seen)
        steps.push_back({K::ready, ""});
    append_extras([&](std::size_t index) { return index >= documented_lines; });
    return steps;
}

}  // namespace

Engine::Engine(const Options& opts)
    : options(opts),
      profile(profile_for(opts.variant)),
      motors(with_dynamics(profile.az, opts.motor.az_velocity, opts.motor),
             with_dynamics(profile.el, opts.motor.el_velocity, opts.motor), profile.skew,
             initial_mechanical_az(profile, opts.start_az), std::clamp(opts.start_el, profile.el.min, profile.el.max)),
      sky(opts.station ? SkyModel(opts.seed, opts.rssi_floor, *opts.station) : SkyModel(opts.seed, opts.rssi_floor)),
      epoch(opts.epoch.value_or(
          std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count())),
      rng(opts.seed ^ 0x5eedu),
      nvs(profile.nvs_table()) {
    menus = {profile.root};
    if (profile.nvs_disable_tracker_index >= 0) {
        // The G2's search runs exactly when NVS 20 is FALSE (§6.2).
        if (NvsEntry* entry = nvs.find(profile.nvs_disable_tracker_index)) {
            const double disabled = opts.search_running ? 0.0 : 1.0;
            entry->current = entry->saved = disabled;
        }
    }
    apply_nvs_limits();
    if (!opts.already_booted) {
        start_boot();
    } else {
        if (profile.needs_homing)
            homed = {opts.g2_homed, opts.g2_homed};
        next_idle_line_ = opts.idle_line_period;
        if (opts.search_running)
            start_search();
    }
    record_sample();
    record_truth();
}

std::string Engine::eol() const {
    switch (options.line_ending) {
        case LineEnding::crlf:
            return "\r\n";
        case LineEnding::lf:
            return "\n";
        case LineEnding::lfcr:
            return "\n\r";
        case LineEnding::cr:
            return "\r";
    }
    return "\r\n";
}

std::string Engine::take_output() {
    if (!options.pace_at_line_rate)
        return on_line_ + std::exchange(output, {});
    return std::exchange(on_line_, {});
}

// 10 bits per byte at the variant's baud rate, in simulated time.
void Engine::run_line(double dt) {
    if (!options.pace_at_line_rate)
        return;
    line_credit_ += dt * profile.baud / 10.0;
    const auto sendable = static_cast<std::size_t>(std::min(line_credit_, static_cast<double>(output.size())));
    on_line_.append(output, 0, sendable);
    output.erase(0, sendable);
    line_credit_ -= static_cast<double>(sendable);
    if (output.empty())
        line_credit_ = std::min(line_credit_, 1.0);  // an idle line saves no time
}

void Engine::print(std::string_view text) {
    output.append(text);
}

void Engine::print_line(std::string_view text) {
    output.append(text);
    output.append(eol());
}

void Engine::print_prompt() {
    const bool named = profile.fixed_prompts || options.prompt_style == PromptStyle::named ||
                       (options.prompt_style == PromptStyle::bare_root && !menus.back()->shell_root);
    output.append(options.prompt_prefix);
    if (named)
        output.append(menus.back()->prompt_name);
    output.push_back('>');
    output.append(options.prompt_suffix);
    if (options.prompt_space)
        output.push_back(' ');
}

void Engine::unknown_command() {
    // The captured G2's text (§6.3); every other console's is unknown (§14 HAL0.4: INVENTED).
    const std::string reply =
        options.unknown_command_reply.value_or(captured_g2() ? "Invalid command" : "Unknown command");
    if (!reply.empty())
        print_line(reply);
}

void Engine::invalid_params() {
    if (captured_g2() && !options.unknown_command_reply) {
        print_line("Invalid params");  // §6.3: a setter without its arguments
        return;
    }
    unknown_command();
}

std::size_t Engine::reply_indent() const {
    return static_cast<std::size_t>(std::clamp(options.position_indent.value_or(captured_g2() ? 4 : 0), 0, 16));
}

HelpLayout Engine::help_layout() const {
    return options.help_layout.value_or(captured_g2() ? HelpLayout::available : HelpLayout::described);
}

double Engine::displayed_az() const {
    return normalize_360(motors.axis(axis_az).position());
}

AzEl Engine::beam_direction() const {
    const AzEl on_sky = dish_to_sky(options.mount, {displayed_az(), motors.axis(axis_el).position()});
    return {normalize_360(on_sky.az), on_sky.el};
}

int Engine::read_rssi() {
    const AzEl beam = beam_direction();
    return sky.read(beam.az, beam.el, lnb_supply, epoch + now);
}

double Engine::reported_az() const {
    return options.az_report == AzReport::displayed ? displayed_az() : motors.axis(axis_az).position();
}

void Engine::apply_nvs_limits() {
    el_min_active_ = profile.el_min;
    el_max_active_ = profile.el_max;
    if (const NvsEntry* entry = nvs.find(profile.nvs_min_el_index))
        el_min_active_ = entry->current;
    if (const NvsEntry* entry = nvs.find(profile.nvs_max_el_index))
        el_max_active_ = entry->current;
}

// --- input ---------------------------------------------------------------------------------

void Engine::record_received(char byte) {
    if (byte == '\r' || byte == '\n') {
        commands.push_back(std::exchange(received_line_, {}));
    } else {
        received_line_.push_back(byte);
    }
}

void Engine::feed(std::string_view bytes) {
    for (const char byte : bytes) {
        // CR LF (X2-style clients, §9.2) is one terminator: the LF neither ends a second,
        // empty line nor counts as the keystroke that aborts a `g`.
        const bool terminator_tail = byte == '\n' && previous_raw_ == '\r';
        previous_raw_ = byte;
        if (terminator_tail)
            continue;
        record_received(byte);
        if ((booting_ && !boot_input_kept_) || !shell_alive)
            continue;  // nobody is reading the UART
        if (!booting_ && now < input_deaf_until_ - 1e-9)
            continue;  // Options::boot_input_drop
        if (busy.kind == Busy::Kind::goto_move && g_aborts_on_input()) {
            motors.stop_all();
            busy.kind = Busy::Kind::until_idle;
        }
        pending_.push_back(byte);
    }
    process_pending();
}

// The shell is single-threaded: typed bytes wait while a command is still running (§6.1).
void Engine::process_pending() {
    while (shell_alive && !booting_ && !pending_.empty()) {
        if (busy.kind == Busy::Kind::stream) {
            // A streaming command reads the UART itself: the next byte ends it and is consumed
            // (§6.3: "run until CR interrupts"); an endless one (PEAK `ts`) swallows everything.
            pending_.erase(0, 1);
            if (!busy.endless)
                end_stream();
            continue;
        }
        if (busy.kind != Busy::Kind::none)
            break;
        const char byte = pending_.front();
        pending_.erase(0, 1);
        if (byte == '\r' || byte == '\n') {
            print(eol());
            execute(std::exchange(line_, {}));
        } else {
            // No line editing (§2): backspace and DEL are ordinary characters.
            line_.push_back(byte);
            if (options.echo)
                output.push_back(byte);
        }
    }
}

void Engine::execute(const std::string& line) {
    const Args args = split_words(line);
    if (args.empty()) {  // bare CR reprints the prompt (§6.1)
        print_prompt();
        return;
    }
    const Menu& menu = *menus.back();
    hazard_counted_for_line_ = false;
    executing_line_ = line;
    if (birdcage::judge_command(core_variant(profile.variant), core_menu_name(menu), line, client_requests).hazard())
        count_hazard();
    const std::string_view word = args.front();
    if (word == "q" || (word == "Q" && captured_g2())) {  // the captured root answers `Q` too (§6.3)
        quit();
        return;
    }
    if (word == "?" || word == "help") {
        help();
        print_prompt();
        return;
    }
    const Command* found = nullptr;
    for (const Command& command : menu.commands) {
        if (command.word == word && (command.available == nullptr || command.available(options))) {
            found = &command;
            break;
        }
    }
    if (found != nullptr && found->submenu != nullptr) {
        menus.push_back(found->submenu);
    } else if (found != nullptr) {
        found->run(*this, args);
    } else if (menu.fallback != nullptr) {
        menu.fallback(*this, args);
    } else {
        unknown_command();
    }
    if (busy.kind == Busy::Kind::none && shell_alive && !booting_)
        print_prompt();
}

void Engine::quit() {
    if (!menus.back()->shell_root) {
        menus.pop_back();
        print_prompt();
        return;
    }
    if (menus.size() > 1 && options.pro_q_at_odu_root_returns_to_idu) {
        menus.pop_back();
        print_prompt();
        return;
    }
    if (menus.size() == 1 && profile.root_q_kills_shell) {
        count_hazard();
        // `Terminating shell.` is what the captured G2 prints when interrupting DVB `ls` ends a
        // shell (§6.5); the reconstruction's text, without the dot, is what the predecessor's
        // probe looked for (§14 G2.2).
        const char* last_words = captured_g2() ? "Terminating shell." : "Terminating shell";
        switch (options.g2_root_q) {
            case G2RootQ::kill:
                kill_shell(last_words);
                return;
            case G2RootQ::restart:
                print_line(last_words);
                break;
            case G2RootQ::harmless:
                break;
        }
    }
    print_prompt();
}

void Engine::help() {
    struct Entry {
        std::string word;
        std::string_view text;
    };
    std::vector<Entry> entries;
    for (const Command& command : menus.back()->commands) {
        if (!command.listed || (command.available != nullptr && !command.available(options)))
            continue;
        entries.push_back({std::string(command.word), command.help});
    }
    const HelpLayout layout = help_layout();
    if (layout == HelpLayout::available) {
        // The captured MOT> listing (§6.3): a title, then each word in a 14-column field after
        // three spaces, then its description; no `q` or `?` entry.
        print_line("Available commands:");
        for (Entry& entry : entries) {
            if (options.help_upper_case)
                for (char& c : entry.word)
                    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
            std::string row = "   " + entry.word;
            row.append(entry.word.size() < 14 ? 14 - entry.word.size() : 1, ' ');
            print_line(row + std::string(entry.text));
        }
        return;
    }
    if (layout == HelpLayout::generated) {
        std::vector<HelpEntry> generated;
        for (const Entry& entry : entries)
            generated.push_back({entry.word, std::string(entry.text)});
        for (const std::string& line : render_help(options.help_grammar, menus.back()->prompt_name, generated))
            print_line(line);
        return;
    }
    entries.push_back({"q", "Quit this menu"});  // INVENTED description
    if (layout != HelpLayout::described)
        entries.push_back({"?", "Help"});  // INVENTED
    std::size_t width = 0;
    for (Entry& entry : entries) {
        if (options.help_upper_case)
            for (char& c : entry.word)
                c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        width = std::max(width, entry.word.size());
    }
    std::string joined;
    for (const Entry& entry : entries) {
        switch (layout) {
            case HelpLayout::described:
                print_line("Enter <" + entry.word + "> - " + std::string(entry.text));
                break;
            case HelpLayout::words:
                print_line(entry.word);
                break;
            case HelpLayout::one_line:
            case HelpLayout::comma_line:
            case HelpLayout::labelled_line:
                if (joined.empty() && layout == HelpLayout::labelled_line)
                    joined = "Commands:";
                if (!joined.empty())
                    joined += layout == HelpLayout::comma_line ? ", " : " ";
                joined += entry.word;
                break;
            case HelpLayout::colon_table:
                print_line(entry.word + std::string(width - entry.word.size(), ' ') + " : " + std::string(entry.text));
                break;
            case HelpLayout::tab_table:
                print_line(entry.word + "\t" + std::string(entry.text));
                break;
            case HelpLayout::available:
            case HelpLayout::generated:
                break;  // rendered above
        }
    }
    if (!joined.empty())
        print_line(joined);
    if (layout == HelpLayout::described)
        print_line("help [<command>]");  // the predecessor's, §6.3
}

void Engine::kill_shell(std::string_view last_words) {
    if (!last_words.empty())
        print_line(last_words);
    shell_alive = false;
    busy = {};
    pending_.clear();
    line_.clear();
}

// --- activities ------------------------------------------------------------------------------

void Engine::wait_until_idle(std::function<void(Engine&)> finish) {
    busy = {Busy::Kind::until_idle, 0.0, 0.0, std::move(finish)};
}

void Engine::wait_for(double seconds, std::function<void(Engine&)> finish) {
    busy = {Busy::Kind::until_time, now + seconds, 0.0, std::move(finish)};
}

void Engine::start_goto(std::function<void(Engine&)> finish) {
    busy = {Busy::Kind::goto_move, 0.0, now, std::move(finish)};
}

void Engine::start_stream(double period, bool drop_to_root, std::function<void(Engine&)> line, bool endless) {
    busy = {Busy::Kind::stream, now + period, 0.0, std::move(line), period, drop_to_root, endless};
}

void Engine::end_stream() {
    const bool drop = busy.drop_to_root;
    busy = {};
    if (drop) {
        print_line("Terminating shell.");  // §6.5: DVB `ls`, PEAK `rssits`
        menus.resize(1);
    }
    print_prompt();
}

void Engine::finish_busy() {
    auto finish = std::move(busy.finish);
    busy = {};
    if (finish)
        finish(*this);
    if (busy.kind == Busy::Kind::none && shell_alive && !booting_)
        print_prompt();
}

void Engine::run_busy() {
    switch (busy.kind) {
        case Busy::Kind::none:
            return;
        case Busy::Kind::until_time:
            if (now >= busy.until - 1e-9)
                finish_busy();
            return;
        case Busy::Kind::stream:
            if (now >= busy.until - 1e-9) {
                busy.until += busy.period;
                if (busy.finish)
                    busy.finish(*this);
            }
            return;
        case Busy::Kind::goto_move:
        case Busy::Kind::until_idle:
            if (busy.kind == Busy::Kind::goto_move && profile.live_goto_output && now >= busy.next_live_line) {
                busy.next_live_line += options.carryout_live_line_period;
                if (busy.finish)
                    busy.finish(*this);  // the live line printer doubles as the final line
            }
            if (!motors.moving())
                finish_busy();
            return;
    }
}

// --- boot, search ------------------------------------------------------------------------------

void Engine::start_boot() {
    motors.stop_all();
    for (std::size_t index : {axis_az, axis_el, axis_skew})
        motors.axis(index).set_position(motors.axis(index).position());
    booting_ = true;
    boot_input_kept_ = false;
    shell_alive = true;
    busy = {};
    pending_.clear();
    line_.clear();
    search = false;
    menus = {profile.root};
    nvs.load_saved();
    apply_nvs_limits();
    nvs_cursor = -1;
    lnb_supply = LnbSupply::stb_18v;
    stall_arms_ = {};  // an injected stall meant for the interrupted move does not hit homing
    const bool keeps_calibration = options.g2_boot_calibrated.value_or(options.g2_console == G2Console::captured);
    if (profile.needs_homing && !keeps_calibration)
        homed = {false, false};
    boot_steps_ = with_extra_boot_lines(profile.boot_script(*this), options.boot_extra);
    boot_index_ = 0;
    boot_resume_at_ = now;
    boot_motion_ = false;
}

void Engine::reboot() {
    start_boot();
}

void Engine::run_boot() {
    if (boot_motion_ && !motors.moving())
        boot_motion_ = false;
    while (booting_ && now >= boot_resume_at_ - 1e-9 && (boot_motion_ || !motors.moving())) {
        if (boot_index_ == boot_steps_.size()) {
            finish_boot();
            return;
        }
        const BootStep& step = boot_steps_[boot_index_++];
        switch (step.kind) {
            case BootStep::Kind::line:
                print_line(step.text);
                // The gap separates one line from the next; a pause or a move sets its own time, and
                // the last line ends the boot at once: a client may answer it straight away (§3.6).
                if (!step.burst && boot_index_ < boot_steps_.size() &&
                    boot_steps_[boot_index_].kind == BootStep::Kind::line)
                    boot_resume_at_ = now + options.boot_line_gap;
                break;
            case BootStep::Kind::raw:
                print(step.text);
                break;
            case BootStep::Kind::move:
                start_boot_moves();
                break;
            case BootStep::Kind::home:
                homed[step.axis] = true;
                break;
            case BootStep::Kind::pause:
                boot_resume_at_ = now + step.seconds;
                break;
            case BootStep::Kind::ready:
                boot_input_kept_ = true;
                break;
        }
    }
}

// The move step just taken, with a hold before the next one if the calibration pauses. With
// Options::boot_moves_overlap, and no homing in the boot, every move of the run it starts is
// queued at once and the boot goes on after the overlap, without waiting for them.
void Engine::start_boot_moves() {
    const auto is_move = [this](std::size_t index) {
        return index < boot_steps_.size() && boot_steps_[index].kind == BootStep::Kind::move;
    };
    const bool homes = std::any_of(boot_steps_.begin(), boot_steps_.end(),
                                   [](const BootStep& step) { return step.kind == BootStep::Kind::home; });
    const bool overlap = options.boot_moves_overlap.has_value() && !homes;
    for (;;) {
        const BootStep& step = boot_steps_[boot_index_ - 1];
        motors.enqueue(step.axis, step.target);
        if (!is_move(boot_index_))
            break;
        if (options.boot_move_pause > 0.0)
            motors.enqueue_hold(boot_steps_[boot_index_].axis, options.boot_move_pause);
        if (!overlap)
            break;
        ++boot_index_;
    }
    if (overlap) {
        boot_motion_ = true;
        boot_resume_at_ = now + *options.boot_moves_overlap;
    }
}

void Engine::finish_boot() {
    booting_ = false;
    boot_input_kept_ = false;
    input_deaf_until_ = now + options.boot_input_drop;
    next_idle_line_ = now + options.idle_line_period;
    bool searching = true;
    if (profile.search_stop == SearchStop::nvs_disable_tracker) {
        const NvsEntry* entry = nvs.find(profile.nvs_disable_tracker_index);
        searching = entry != nullptr && entry->current == 0.0 && homed[axis_az] && homed[axis_el];
    }
    if (profile.boot_prints_prompt && !searching)
        print_prompt();
    if (searching)
        start_search();
}

void Engine::start_search() {
    search = true;
    search_resume_at = now;
    search_ends_at = now + options.carryout_search_seconds;
}

void Engine::stop_search() {
    search = false;
    // The search waits for the boot's moves (run_search), so while they run it has moved nothing:
    // stopping it leaves them running.
    if (!boot_motion_)
        motors.stop_all();
}

void Engine::run_search() {
    if (!search || booting_)
        return;
    if (profile.search_stop == SearchStop::runs_out && now >= search_ends_at) {
        stop_search();
        return;
    }
    if (motors.moving() || busy.kind != Busy::Kind::none) {
        search_resume_at = now + search_dwell;
        return;
    }
    if (now < search_resume_at)
        return;
    const double margin = 5.0;
    std::uniform_real_distribution<double> az(profile.az.min + margin, profile.az.max - margin);
    std::uniform_real_distribution<double> el(el_limit_min(), el_limit_max());
    motors.enqueue(axis_az, az(rng));
    motors.enqueue(axis_el, el(rng));
}

// --- time ----------------------------------------------------------------------------------------

// Every tick while the dish moves; at rest one sample a second keeps long idle runs small.
void Engine::record_sample() {
    const Sample sample{now, displayed_az(), motors.axis(axis_el).position()};
    if (!history.empty()) {
        const Sample& last = history.back();
        const bool still = last.az == sample.az && last.el == sample.el;
        if (now - last.t < (still ? 1.0 : max_tick) - 1e-9)
            return;
    }
    history.push_back(sample);
}

// A row on every 0.1 s of the grid and at every start and end of motion, so that a test reading
// the file sees each motion's exact ends.
void Engine::record_truth() {
    if (options.truth_path.empty())
        return;
    const bool moving_now = motors.moving();
    const bool due = now >= next_truth_at_ - 1e-9;
    if (!due && moving_now == truth_moving_)
        return;
    if (due)
        next_truth_at_ = (std::floor(now / truth_period + 1e-6) + 1.0) * truth_period;
    truth_moving_ = moving_now;
    const AzEl beam = beam_direction();
    truth.push_back({now, displayed_az(), motors.axis(axis_el).position(), beam.az, beam.el, moving_now});
}

// --- injected motor stalls -------------------------------------------------------------------

void Engine::inject_motor_stall(std::size_t axis) {
    if (axis != axis_az && axis != axis_el)
        return;
    stall_arms_[axis] = StallArm{true, false, 0.0, 0.0, 0.0};
}

void Engine::run_stalls() {
    for (const std::size_t index : {axis_az, axis_el}) {
        StallArm& arm = stall_arms_[index];
        Axis& axis = motors.axis(index);
        if (!arm.armed)
            continue;
        if (!axis.moving()) {
            arm.tracking = false;  // that move ended short of the stall point: wait for the next
            continue;
        }
        if (!arm.tracking || arm.target != axis.target()) {
            // First seen moving (within one tick of the start): stall halfway to the target.
            arm.tracking = true;
            arm.target = axis.target();
            arm.stall_at = 0.5 * (axis.position() + axis.target());
            arm.direction = axis.target() >= axis.position() ? 1.0 : -1.0;
        }
        if ((axis.position() - arm.stall_at) * arm.direction < 0.0)
            continue;
        arm = {};
        motors.stop_all();                   // the firmware abandons the rest of the command
        axis.set_position(axis.position());  // a stalled stepper stops dead
        ++motor_stalls;
        // §6.3 / §3.3 text; where it lands relative to the prompt is INVENTED (printed when it
        // happens, no prompt reprint; a waiting command prints its prompt when motion ends).
        print_line(index == axis_az ? "AZ MOTOR STALLED" : "EL MOTOR STALLED");
    }
}

// Unsolicited output from another firmware task: it lands wherever the shell happens to be.
void Engine::run_idle_line() {
    if (options.idle_line_period <= 0.0 || options.idle_line.empty() || booting_ || !shell_alive)
        return;
    if (now < next_idle_line_ - 1e-9)
        return;
    next_idle_line_ = now + options.idle_line_period;
    print_line(options.idle_line);
}

void Engine::tick() {
    run_stalls();
    run_boot();
    run_search();
    run_busy();
    process_pending();
    run_idle_line();
    record_sample();
    record_truth();
}

void Engine::advance(double dt) {
    while (dt > 0.0) {
        const double step = std::min(dt, max_tick);
        dt -= step;
        motors.advance(step);
        now += step;
        tick();
        run_line(step);
    }
}

}  // namespace birdcage::sim
