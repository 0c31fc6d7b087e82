// birdcage dish emulator: a pty that behaves like the serial console of a Winegard motorized
// dish. Written from /work/shared/notes/firmware.md (section numbers cited as §n), independently
// of the backend in src/, so that it can act as the test oracle.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace birdcage::sim {

enum class Variant { travler_hal000, travler_hal205, travler_pro, carryout2003, carryout_g2 };

// "hal000", "hal205", "pro", "carryout2003", "g2"
std::optional<Variant> parse_variant(std::string_view name);
const char* variant_name(Variant);

// Switches for behaviour firmware.md §14 lists as unknown. Defaults are the most plausible
// reading of the notes; text marked INVENTED is not known firmware output.
enum class LineEnding { crlf, lf };          // §14 HAL0.6, G2.10; bare CR reply "CR LF then TRK>" (§6.1)
enum class AzReport { displayed, mechanical };  // §14 G2.4 (and §3.3: `a` may show the wrap)
enum class OutOfRange { clamp, reject };     // §14 HAL0.4, G2.6; §3.4 "unreliable below 15"
enum class MoveAck { immediate, after_motion };  // §14 G2.3
enum class PromptStyle { named, bare };      // Trav'ler/Carryout 2003 prompts, §14 HAL0.1, CO.2
enum class BootMarker { no_gps, no_lnb_voltage };  // HAL 2.05 boot-complete line, §4.2
// Transcript replay (docs/transcripts.md): strict stops at the first unexpected command and reports
// it through Emulator::replay_failure(); lenient hands the session over to the model console.
enum class ReplayMode { off, strict, lenient };

struct Options {
    Variant variant = Variant::carryout_g2;
    double time_scale = 1.0;      // simulated seconds per real second
    bool already_booted = true;   // false: boot log first (scaled time), then post-boot behaviour
    bool search_running = false;  // with already_booted: the TV-satellite search is running
    double start_az = 180.0, start_el = 45.0;  // true position at start (mapped into the wrap window)
    std::string link_path;        // if non-empty: symlink to the pty slave, removed on destruction
    std::uint32_t seed = 1;       // RSSI noise, search wander

    // --- unknown-behaviour switches -----------------------------------------------------
    bool echo = true;             // §6.1 (G2: strong evidence), §3.1 / §14 (others: hints only)
    LineEnding line_ending = LineEnding::crlf;
    // §14 HAL0.4 / G2.6: the text is undocumented. INVENTED default. Empty = print nothing.
    std::string unknown_command_reply = "Unknown command";
    OutOfRange out_of_range = OutOfRange::clamp;
    // Printed instead of moving when out_of_range == reject. INVENTED default.
    std::string out_of_range_reply = "Angle out of range";
    // §14 G2.3: `a <id> <deg>` ack + prompt right away (motion continues in the background)
    // or only when the commanded motion has finished.
    MoveAck move_ack = MoveAck::immediate;
    // false: a position query issued while moving is answered once the dish has stopped.
    bool answer_position_while_moving = true;
    AzReport az_report = AzReport::displayed;
    // §2 / §3.5: any byte received during `g` aborts it. §8.5 says the 2003 Carryout's scans
    // send `q` right after `g` and still move, so this may be false there.
    bool g_aborts_on_input = true;
    // §6.5 vs §14 G2.2: `q` at TRK> kills the shell (console dead until power cycle).
    bool g2_root_q_kills_shell = true;
    // G2 with already_booted: axes calibrated (true) or reading INT_MAX until `h` (false), §6.4.
    bool g2_homed = true;
    // §6.2 caveat / §14 G2.7: does boot homing run when NVS 20 (Disable Tracker Proc) is TRUE?
    bool g2_boot_homes = true;
    PromptStyle prompt_style = PromptStyle::named;  // Trav'ler, Pro, Carryout 2003 only
    BootMarker hal205_boot_marker = BootMarker::no_gps;  // §4.2
    bool hal205_accepts_mot = false;  // §14 HAL2.05.4: does `mot` work besides `motor`?
    // §14 Pro.2: does `q` at the ODU root return to the IDU console? The Pro client sends
    // `odu`, `q`, CR, `mot` (§5.6), which only works if it does not.
    bool pro_q_at_odu_root_returns_to_idu = false;
    // §8.2: the 2003 Carryout's search cannot be stopped from the console; it ends by itself
    // (calibration + search take 10-15 min). Simulated seconds of wandering.
    double carryout_search_seconds = 600.0;
    double rssi_floor = 401.0;  // §11.2 (Davidson ~400 with lnbdc odu; birdcage ~500, §14 G2.14)

    // --- transcript replay ------------------------------------------------------------------
    // With a mode other than off, the dish answers from this transcript (recorded timing divided
    // by time_scale) instead of the model; the constructor throws TranscriptError if it is bad.
    std::string transcript_path;
    ReplayMode replay = ReplayMode::off;

    // Console traffic observer, called from the console thread. from_client: bytes the client
    // wrote; otherwise bytes the dish sent.
    std::function<void(bool from_client, std::string_view bytes)> trace;
};

struct Pose {
    double az;
    double el;
};
struct Sample {
    double t;
    double az;
    double el;
};

class Console;

// RAII: the constructor opens the pty and starts the console thread; the destructor stops the
// thread, closes the pty and removes the symlink. All accessors are thread-safe.
class Emulator {
public:
    explicit Emulator(Options);
    ~Emulator();
    Emulator(const Emulator&) = delete;
    Emulator& operator=(const Emulator&) = delete;

    const std::string& device_path() const;  // link_path if given, else /dev/pts/N
    Pose true_position() const;              // displayed az in [0,360), el
    double true_mechanical_az() const;       // az including cable-wrap turns
    bool moving() const;
    bool search_running() const;
    std::vector<Sample> history() const;     // true position over simulated time
    unsigned hazards_received() const;
    std::vector<std::string> received_commands() const;  // every complete line, in order (empty lines included)
    double sim_time() const;
    void power_cycle();                      // reboot: boot log, search restart, menu at root
    bool shell_alive() const;                // false after a G2 root `q` or an ADC `scan` deadlock

    // Replay only. The diff at the first unexpected command (strict mode), escaped, with the
    // transcript line number; nullopt while the session follows the transcript.
    std::optional<std::string> replay_failure() const;
    bool replay_complete() const;            // every transcript chunk was matched or sent
    bool replay_fell_back() const;           // lenient mode handed over to the model console

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace birdcage::sim
