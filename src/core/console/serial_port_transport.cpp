// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "console/serial_port_transport.hpp"

#include <libserialport.h>

namespace birdcage {
namespace {

// The one place sp_return becomes an Errc.
Status sp_status(const char* operation, sp_return code) {
    switch (code) {
        case SP_OK:
            return Status::ok();
        case SP_ERR_ARG:
            return Status{Errc::invalid_argument, std::string(operation) + ": invalid argument or no such port"};
        case SP_ERR_SUPP:
            return Status{Errc::unsupported, std::string(operation) + ": not supported by this port"};
        case SP_ERR_MEM:
            return Status{Errc::io, std::string(operation) + ": out of memory"};
        case SP_ERR_FAIL: {
            char* text = sp_last_error_message();
            std::string message = std::string(operation) + ": " + (text != nullptr ? text : "failed");
            sp_free_error_message(text);
            return Status{Errc::io, message};
        }
    }
    return Status{Errc::io, std::string(operation) + ": unknown libserialport error"};
}

unsigned int timeout_ms(Deadline deadline) {
    const auto remaining = deadline - Clock::now();
    if (remaining <= Clock::duration::zero()) {
        return 0;
    }
    const auto ms = std::chrono::ceil<std::chrono::milliseconds>(remaining).count();
    return ms > 60'000 ? 60'000u : static_cast<unsigned int>(ms);
}

}  // namespace

void SerialPortTransport::PortDeleter::operator()(sp_port* port) const {
    sp_close(port);
    sp_free_port(port);
}

SerialPortTransport::SerialPortTransport(std::unique_ptr<sp_port, PortDeleter> port) : port_(std::move(port)) {}

Result<std::unique_ptr<SerialPortTransport>> SerialPortTransport::open(const std::string& path, int baud) {
    sp_port* raw = nullptr;
    if (const auto code = sp_get_port_by_name(path.c_str(), &raw); code != SP_OK) {
        auto status = sp_status("sp_get_port_by_name", code);
        status.message = "cannot use serial port " + path + " (" + status.message + ")";
        return {nullptr, status};
    }
    if (const auto code = sp_open(raw, SP_MODE_READ_WRITE); code != SP_OK) {
        auto status = sp_status("sp_open", code);
        status.message = "cannot open serial port " + path + " (" + status.message + ")";
        sp_free_port(raw);
        return {nullptr, status};
    }
    std::unique_ptr<sp_port, PortDeleter> port(raw);
    const sp_return steps[] = {sp_set_baudrate(port.get(), baud), sp_set_bits(port.get(), 8),
                               sp_set_parity(port.get(), SP_PARITY_NONE), sp_set_stopbits(port.get(), 1),
                               sp_set_flowcontrol(port.get(), SP_FLOWCONTROL_NONE)};
    for (const auto code : steps) {
        if (code != SP_OK) {
            auto status = sp_status("configure", code);
            status.message =
                "cannot configure " + path + " for " + std::to_string(baud) + " 8N1 (" + status.message + ")";
            return {nullptr, status};
        }
    }
    return {std::unique_ptr<SerialPortTransport>(new SerialPortTransport(std::move(port))), Status::ok()};
}

Status SerialPortTransport::write(std::string_view bytes, Deadline deadline) {
    // libserialport treats a timeout of 0 as "wait forever", so never pass 0.
    const unsigned int ms = timeout_ms(deadline);
    const int written = sp_blocking_write(port_.get(), bytes.data(), bytes.size(), ms == 0 ? 1 : ms);
    if (written < 0) {
        return sp_status("sp_blocking_write", static_cast<sp_return>(written));
    }
    if (static_cast<std::size_t>(written) < bytes.size()) {
        return Status{Errc::timeout, "write timed out"};
    }
    return Status::ok();
}

Result<std::size_t> SerialPortTransport::read(char* buf, std::size_t n, Deadline deadline) {
    const unsigned int ms = timeout_ms(deadline);
    const int got = ms == 0 ? sp_nonblocking_read(port_.get(), buf, n) : sp_blocking_read_next(port_.get(), buf, n, ms);
    if (got < 0) {
        return {0, sp_status("sp_blocking_read_next", static_cast<sp_return>(got))};
    }
    if (got == 0) {
        return {0, Status{Errc::timeout, "no data before the deadline"}};
    }
    return {static_cast<std::size_t>(got), Status::ok()};
}

void SerialPortTransport::discard_input() {
    sp_flush(port_.get(), SP_BUF_INPUT);
}

}  // namespace birdcage
