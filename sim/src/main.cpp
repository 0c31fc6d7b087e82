// birdcage-sim: run one emulated dish on a pty until SIGINT/SIGTERM.
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <optional>
#include <pthread.h>
#include <string>
#include <string_view>

#include "birdcage_sim/emulator.hpp"

namespace {

void usage()
{
    std::cerr << "usage: birdcage-sim --variant hal205|g2|hal000|pro|carryout2003 [--link PATH]\n"
                 "                    [--time-scale X] [--booting] [--search] [--az A --el E] [--trace]\n";
}

std::string escaped(std::string_view bytes)
{
    std::string text;
    for (const char c : bytes) {
        const auto byte = static_cast<unsigned char>(c);
        if (c == '\r') text += "\\r";
        else if (c == '\n') text += "\\n";
        else if (c == '\\') text += "\\\\";
        else if (byte < 0x20 || byte >= 0x7f) {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", byte);
            text += hex;
        } else text += c;
    }
    return text;
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
        } else if (arg == "--booting") {
            options.already_booted = false;
        } else if (arg == "--search") {
            options.search_running = true;
        } else if (arg == "--trace") {
            options.trace = [](bool from_client, std::string_view bytes) {
                std::cerr << (from_client ? "<< " : ">> ") << escaped(bytes) << '\n';
            };
        } else {
            usage();
            return 2;
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
        int signal_number = 0;
        sigwait(&stop_signals, &signal_number);
    } catch (const std::exception& error) {
        std::cerr << "birdcage-sim: " << error.what() << '\n';
        return 1;
    }
    return 0;
}
