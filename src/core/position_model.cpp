#include "birdcage/position_model.hpp"

#include <algorithm>
#include <chrono>

namespace birdcage {

AzEl modelled_position(const FirmwareProfile& dish, AzEl last, const std::optional<LegMotion>& leg,
                       Clock::time_point now) {
    if (!leg) {
        return last;
    }
    const bool azimuth = leg->axis == Axis::azimuth;
    const double distance = azimuth ? azimuth_difference(leg->from, leg->to) : leg->to - leg->from;
    const double move_s = std::chrono::duration<double>(estimated_move_time(dish, leg->axis, distance)).count();
    const auto started = std::max(leg->from_at, leg->sent_at);
    const double elapsed = std::chrono::duration<double>(now - started).count();
    if (move_s <= 0.0 || elapsed <= 0.0) {
        return last;
    }
    // From the last reading: a reading taken mid-move leaves the remaining distance to cover.
    const double u = std::clamp(elapsed / move_s, 0.0, 1.0);
    const double travelled = distance * u * u * (3.0 - 2.0 * u);
    if (azimuth) {
        last.az = normalize_azimuth(leg->from + travelled);
    } else {
        last.el = leg->from + travelled;
    }
    return last;
}

}  // namespace birdcage
