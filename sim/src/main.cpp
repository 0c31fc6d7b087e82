// birdcage-sim: run one emulated dish on a pty until SIGINT/SIGTERM.
#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <optional>
#include <pthread.h>
#include <string>
#include <string_view>

#include "birdcage_sim/emulator.hpp"
#include "birdcage_sim/transcript.hpp"

namespace {

void usage()
{
    std::cerr << "usage: birdcage-sim --variant hal205|g2|hal000|pro|carryout2003 [--link PATH]\n"
                 "                    [--time-scale X] [--booting] [--search] [--az A --el E] [--trace]\n"
                 "                    [--replay TRANSCRIPT [--lenient]]   (--variant defaults to the transcript's)\n"
                 "                    [--idle-noise BPS] [--invert] [--ignore-input] [--drop P] [--pace BAUD]\n"
                 "                    [--seed N]   (line faults; BPS and BAUD in real time)\n"
                 "                    [--az-mapping nearest|literal|wrap_manager] [--az-wrap-point DEG]\n";
}

std::optional<double> number(const char* text)
{
    char* end = nullptr;
    const double value = std::strtod(text, &end);
    if (end == text || *end != '\0') return std::nullopt;
    return value;
}

}  // namespace

int main(int argc, char** argv)
{
    birdcage::sim::Options options;
    bool have_variant = false;
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        const bool has_value = i + 1 < argc;
        if (arg == "--variant" && has_value) {
            const auto variant = birdcage::sim::parse_variant(argv[++i]);
            if (!variant) {
                usage();
                return 2;
            }
            options.variant = *variant;
            have_variant = true;
        } else if (arg == "--link" && has_value) {
            options.link_path = argv[++i];
        } else if ((arg == "--time-scale" || arg == "--az" || arg == "--el") && has_value) {
            const auto value = number(argv[++i]);
            if (!value || (arg == "--time-scale" && *value <= 0.0)) {
                usage();
                return 2;
            }
            (arg == "--time-scale" ? options.time_scale : arg == "--az" ? options.start_az : options.start_el) = *value;
        } else if ((arg == "--idle-noise" || arg == "--drop" || arg == "--pace" || arg == "--seed") && has_value) {
            const auto value = number(argv[++i]);
            const bool integral = arg == "--pace" || arg == "--seed";
            if (!value || *value < 0.0 || (arg == "--drop" && *value > 1.0) ||
                (integral && (*value != static_cast<double>(static_cast<long>(*value)) || *value > 4294967295.0))) {
                usage();
                return 2;
            }
            if (arg == "--idle-noise") options.line_faults.idle_noise_bps = *value;
            if (arg == "--drop") options.line_faults.drop_probability = *value;
            if (arg == "--pace") options.line_faults.pace_baud = static_cast<int>(std::min(*value, 1e9));
            if (arg == "--seed") options.seed = static_cast<std::uint32_t>(*value);
        } else if (arg == "--az-mapping" && has_value) {
            const auto mapping = birdcage::sim::parse_az_mapping(argv[++i]);
            if (!mapping) {
                usage();
                return 2;
            }
            options.az_mapping = *mapping;
        } else if (arg == "--az-wrap-point" && has_value) {
            const auto value = number(argv[++i]);
            if (!value || !std::isfinite(*value)) {
                usage();
                return 2;
            }
            options.az_wrap_point = *value;
        } else if (arg == "--invert") {
            options.line_faults.inverted_polarity = true;
        } else if (arg == "--ignore-input") {
            options.line_faults.ignore_input = true;
        } else if (arg == "--replay" && has_value) {
            options.transcript_path = argv[++i];
            if (options.replay == birdcage::sim::ReplayMode::off) options.replay = birdcage::sim::ReplayMode::strict;
        } else if (arg == "--lenient") {
            options.replay = birdcage::sim::ReplayMode::lenient;
        } else if (arg == "--booting") {
            options.already_booted = false;
        } else if (arg == "--search") {
            options.search_running = true;
        } else if (arg == "--trace") {
            options.trace = [](bool from_client, std::string_view bytes) {
                std::cerr << (from_client ? "<< " : ">> ") << birdcage::sim::escape_chunk(bytes) << '\n';
            };
        } else {
            usage();
            return 2;
        }
    }
    if (options.replay != birdcage::sim::ReplayMode::off && options.transcript_path.empty()) {
        usage();
        return 2;
    }
    if (!have_variant && !options.transcript_path.empty()) {
        try {
            const auto variant_name = birdcage::sim::load_transcript(options.transcript_path).header("Variant");
            const auto variant = variant_name ? birdcage::sim::parse_variant(*variant_name) : std::nullopt;
            if (variant) {
                options.variant = *variant;
                have_variant = true;
            }
        } catch (const std::exception& error) {
            std::cerr << "birdcage-sim: " << error.what() << '\n';
            return 1;
        }
    }
    if (!have_variant) {
        usage();
        return 2;
    }

    // Block the signals before the console thread exists so that only sigwait sees them.
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

    try {
        birdcage::sim::Emulator emulator(options);
        std::cout << "device: " << emulator.device_path() << std::endl;
        // A strict replay that fails has nothing more to say: report the diff and stop.
        const timespec check_period{0, 100'000'000};
        bool reported_complete = false;
        for (;;) {
            if (sigtimedwait(&stop_signals, nullptr, &check_period) >= 0) break;
            if (const auto failure = emulator.replay_failure()) {
                std::cerr << *failure;
                return 1;
            }
            if (!reported_complete && emulator.replay_complete()) {
                std::cerr << "birdcage-sim: replay complete\n";
                reported_complete = true;
            }
        }
    } catch (const std::exception& error) {
        std::cerr << "birdcage-sim: " << error.what() << '\n';
        return 1;
    }
    return 0;
}
