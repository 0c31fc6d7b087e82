// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The rotctld client library (src/client/): reply parsing in the plain and extended protocols,
// RPRT codes as names, and the client against a scripted rotctld on a loopback socket (what the
// real one answers is tested end to end in tests/e2e and tests/tui).
#include "rotctl_client.hpp"

#include <catch2/catch.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <functional>
#include <map>
#include <thread>

using namespace birdcage::rotctl;
using namespace std::chrono_literals;

TEST_CASE("plain replies: values, an RPRT line instead, and set commands") {
    std::string buffer = "100.00\n";
    CHECK_FALSE(take_reply(buffer, Protocol::plain, Shape::values(2)));
    CHECK(buffer == "100.00\n");  // an incomplete reply is left for later
    buffer += "30.00\nRPRT 0\n";
    const auto p = take_reply(buffer, Protocol::plain, Shape::values(2));
    REQUIRE(p);
    CHECK(p->ok());
    CHECK(p->lines == std::vector<std::string>{"100.00", "30.00"});
    const auto set = take_reply(buffer, Protocol::plain, Shape::values(0));
    REQUIRE(set);
    CHECK(set->ok());
    CHECK(buffer.empty());

    buffer = "RPRT -5\n";
    const auto failed = take_reply(buffer, Protocol::plain, Shape::values(2));
    REQUIRE(failed);
    CHECK(failed->code == -5);
    CHECK(failed->lines.empty());
}

TEST_CASE("extended replies, one field a line and semicolon-separated, as rotctld 4.5 prints them") {
    std::string buffer = "get_pos:\nAzimuth: 100.00\nElevation: 30.00\n";
    CHECK_FALSE(take_reply(buffer, Protocol::extended, Shape::values(2)));
    buffer += "RPRT 0\n";
    const auto r = take_reply(buffer, Protocol::extended, Shape::values(2));
    REQUIRE(r);
    CHECK(r->values() == std::vector<std::string>{"100.00", "30.00"});
    CHECK(*parse_number(r->lines[0]) == Approx(100.0));

    buffer = "get_pos:;Azimuth: 1.50;Elevation: -2.25;RPRT 0\n";
    const auto s = take_reply(buffer, Protocol::extended_semicolon, Shape::values(2));
    REQUIRE(s);
    CHECK(s->ok());
    CHECK(s->values() == std::vector<std::string>{"1.50", "-2.25"});

    // An unknown command is answered with RPRT alone, no header.
    buffer = "RPRT -11\n";
    const auto e = take_reply(buffer, Protocol::extended, Shape::values(1));
    REQUIRE(e);
    CHECK(e->code == -11);

    buffer = "get_info:\nInfo: Winegard G2: limits az 0..360\nRPRT 0\n";
    CHECK(take_reply(buffer, Protocol::extended, Shape::values(1))->values().front() ==
          "Winegard G2: limits az 0..360");
    // An idle rotator's status: the key alone.
    buffer = "get_status:\nStatus flags: \nRPRT 0\n";
    CHECK(take_reply(buffer, Protocol::extended, Shape::values(1))->values() == std::vector<std::string>{""});
    CHECK(request("p", Protocol::extended) == "+p\n");
    CHECK(request("p", Protocol::extended_semicolon) == ";p\n");
}

TEST_CASE("RPRT codes have Hamlib's names and texts") {
    CHECK(error_name(code(Errc::io)) == "RIG_EIO");
    CHECK(error_name(-1) == "RIG_EINVAL");
    CHECK(error_name(-20) == "RIG_EPOWER");
    CHECK(error_name(-99) == "RIG_E?(-99)");
    CHECK(error_text(-5) == "Communication timed out");
    CHECK(error_text(-11) == "Feature not available");
    CHECK(error_text(-42) == "error -42");
}

TEST_CASE("dump_state limits in Hamlib 4's form, the extended form and Hamlib 3's") {
    const auto four = parse_dump_state({"1", "90102", "min_az=-180.000000", "max_az=450.000000", "min_el=0.000000",
                                        "max_el=90.000000", "south_zero=0"});
    REQUIRE(four);
    CHECK(four->min_az == -180.0);
    CHECK(four->max_az == 450.0);
    CHECK(four->max_el == 90.0);
    CHECK(four->contains(400, 10));
    CHECK_FALSE(four->contains(999, 40));
    const auto extended = parse_dump_state({"rotctld Protocol Ver: 1", "Rotor Model: 1", "Minimum Azimuth: 0.000000",
                                            "Maximum Azimuth: 360.000000", "Minimum Elevation: 15.000000",
                                            "Maximum Elevation: 65.000000"});
    REQUIRE(extended);
    CHECK(extended->min_el == 15.0);
    const auto three = parse_dump_state({"0", "2", "0.000000", "360.000000", "5.000000", "70.000000"});
    REQUIRE(three);
    CHECK(three->max_el == 70.0);
    CHECK_FALSE(parse_dump_state({"1", "1", "min_az=0"}));
}

TEST_CASE("dump_caps: model, flags and the extension levels") {
    const Caps c =
        parse_dump_caps({"Caps dump for model:\t90102", "Model name:\tCarryout G2", "Mfg name:\tWinegard",
                         "Backend version:\tbirdcage 0.1.0", "Can Park:\tY", "Can Reset:\tN", "Can get Status:\tY",
                         "Min Azimuth:\t-180.00", "Max Azimuth:\t540.00", "Min Elevation:\t0.00",
                         "Max Elevation:\t90.00", "Extra levels:", "\tRSSI", "\t\tLabel:\tSignal strength",
                         "\t\tRange:\t0..1000/0", "\tLNB", "\t\tLabel:\tLNB supply (V)", "Get parameters: "});
    CHECK(c.model == "Winegard Carryout G2");
    CHECK(c.backend == "birdcage 0.1.0");
    CHECK(c.can_park);
    CHECK_FALSE(c.can_reset);
    CHECK(c.can_status);
    REQUIRE(c.levels.size() == 2);
    CHECK(c.levels[0].name == "RSSI");
    CHECK(c.levels[1].label == "LNB supply (V)");
    REQUIRE(c.limits);
    CHECK(c.limits->min_az == -180.0);
    CHECK(c.limits->max_el == 90.0);
}

TEST_CASE("the birdcage backend's `_` narrows the elevation range to the dish's own") {
    const Limits caps{-180, 540, 0, 90};
    const Limits g2 = narrowed_by_info(caps,
                                       "Winegard Carryout G2 [g2, 115200 baud]; initialised; position az 121.00 "
                                       "el 30.00 (read back); el limits 18.00..65.00; leapfrog off");
    CHECK(g2.min_el == 18.0);
    CHECK(g2.max_el == 65.0);
    CHECK(g2.min_az == -180.0);
    CHECK(g2.max_az == 540.0);
    CHECK(narrowed_by_info(caps, "Dummy rotator").max_el == 90.0);
}

namespace {

// A scripted rotctld: answers each command line from `answers` (an unknown one with RPRT -11),
// and drops the connection when told to.
class FakeRotctld {
public:
    explicit FakeRotctld(std::map<std::string, std::string> answers) : answers_(std::move(answers)) {
        listen_fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in addr{};
        addr.sin_family = AF_INET;
        addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        REQUIRE(::bind(listen_fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0);
        socklen_t length = sizeof addr;
        ::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&addr), &length);
        port_ = ntohs(addr.sin_port);
        REQUIRE(::listen(listen_fd_, 4) == 0);
        thread_ = std::thread([this] { serve(); });
    }
    ~FakeRotctld() {
        stopping_ = true;
        ::shutdown(listen_fd_, SHUT_RDWR);
        thread_.join();
        ::close(listen_fd_);
    }
    int port() const { return port_; }
    void drop() { drop_ = true; }
    int accepted() const { return accepted_; }

private:
    void serve() {
        while (!stopping_) {
            pollfd p{listen_fd_, POLLIN, 0};
            if (::poll(&p, 1, 20) <= 0)
                continue;
            const int fd = ::accept(listen_fd_, nullptr, nullptr);
            if (fd < 0)
                continue;
            ++accepted_;
            std::string in;
            while (!stopping_ && !drop_) {
                pollfd c{fd, POLLIN, 0};
                if (::poll(&c, 1, 20) <= 0)
                    continue;
                char buffer[256];
                const ssize_t got = ::recv(fd, buffer, sizeof buffer, 0);
                if (got <= 0)
                    break;
                in.append(buffer, static_cast<std::size_t>(got));
                for (auto nl = in.find('\n'); nl != std::string::npos; nl = in.find('\n')) {
                    const std::string line = in.substr(0, nl);
                    in.erase(0, nl + 1);
                    const auto a = answers_.find(line);
                    const std::string out = a == answers_.end() ? "RPRT -11\n" : a->second;
                    (void)::send(fd, out.data(), out.size(), MSG_NOSIGNAL);
                }
            }
            ::close(fd);
            drop_ = false;
        }
    }

    std::map<std::string, std::string> answers_;
    int listen_fd_ = -1;
    int port_ = 0;
    std::atomic<bool> stopping_{false}, drop_{false};
    std::atomic<int> accepted_{0};
    std::thread thread_;
};

const std::map<std::string, std::string> kAnswers = {
    {"+p", "get_pos:\nAzimuth: 174.00\nElevation: 44.00\nRPRT 0\n"},
    {"p", "174.00\n44.00\n"},
    {"+P 999.00 40.00", "set_pos: 999.00 40.00\nRPRT -1\n"},
    {"+s", "get_status:\nStatus flags: MOVING_AZ MOVING\nRPRT 0\n"},
    {"+v RSSI", "get_level: RSSI\n512\nRPRT 0\n"},
    {"+v ?", "get_level: ?\nRSSI RSSI_SAMPLES LNB \nRPRT 0\n"},
    {"\\dump_state", "1\n90102\nmin_az=0.000000\nmax_az=360.000000\nmin_el=15.000000\nmax_el=65.000000\ndone\n"},
};

bool wait_for_closed(const Client& client) {
    for (int i = 0; i < 1000 && !client.peer_closed(); ++i) {
        std::this_thread::sleep_for(5ms);
    }
    return client.peer_closed();
}

}  // namespace

TEST_CASE("the client against a scripted rotctld: commands, typed errors, limits") {
    FakeRotctld fake(kAnswers);
    Client client("127.0.0.1", fake.port());
    std::string why;
    REQUIRE(client.connect(&why));
    double az = 0, el = 0;
    CHECK(client.get_position(az, el) == 0);
    CHECK(az == 174.0);
    CHECK(el == 44.0);
    CHECK(client.set_position(999, 40) == code(Errc::inval));
    std::string flags;
    CHECK(client.get_status(flags) == 0);
    CHECK(flags == "MOVING_AZ MOVING");
    double rssi = 0;
    CHECK(client.get_level(level::rssi, rssi) == 0);
    CHECK(rssi == 512.0);
    std::vector<std::string> names;
    CHECK(client.ext_levels(names) == 0);
    CHECK(names == std::vector<std::string>{"RSSI", "RSSI_SAMPLES", "LNB"});
    Limits limits;
    CHECK(client.get_limits(limits) == 0);
    CHECK(limits.min_el == 15.0);
    CHECK(limits.max_el == 65.0);
    CHECK(client.park() == code(Errc::navail));  // the fake knows no K
    CHECK(client.connected());
}

TEST_CASE("the plain protocol, as Gpredict speaks it") {
    FakeRotctld fake(kAnswers);
    Client client("127.0.0.1", fake.port(), Options{.protocol = Protocol::plain});
    REQUIRE(client.connect());
    double az = 0, el = 0;
    CHECK(client.get_position(az, el) == 0);
    CHECK(az == 174.0);
}

TEST_CASE("a lost link reads RIG_EIO, and reconnect() opens it again after the back-off") {
    FakeRotctld fake(kAnswers);
    Client client("127.0.0.1", fake.port(), Options{.timeout = 2s});
    REQUIRE(client.connect());
    fake.drop();
    REQUIRE(wait_for_closed(client));
    double az = 0, el = 0;
    CHECK(client.get_position(az, el) == code(Errc::io));
    CHECK_FALSE(client.connected());

    Backoff backoff(1ms, 4ms);
    std::vector<long> waits;
    CHECK(client.reconnect(backoff, [&](std::chrono::milliseconds d) {
        waits.push_back(d.count());
        return true;
    }));
    CHECK(waits.empty());  // the rotctld is back at once: no wait
    CHECK(fake.accepted() == 2);
    CHECK(client.get_position(az, el) == 0);
}

TEST_CASE("reconnecting to nobody waits the doubling back-off and gives up when told") {
    int port = 0;
    {
        FakeRotctld gone(kAnswers);
        port = gone.port();
    }
    Client client("127.0.0.1", port, Options{.connect_timeout = 200ms});
    Backoff backoff(10ms, 40ms);
    std::vector<long> waits;
    std::string why;
    CHECK_FALSE(client.reconnect(
        backoff,
        [&](std::chrono::milliseconds d) {
            waits.push_back(d.count());
            return waits.size() < 4;
        },
        &why));
    CHECK(waits == std::vector<long>{10, 20, 40, 40});
    CHECK(why.find("cannot connect to 127.0.0.1:") == 0);
}
