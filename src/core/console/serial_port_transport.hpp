// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Real serial ports through libserialport, for standalone tools.
#pragma once

#include <memory>
#include <string>

#include "console/transport.hpp"

struct sp_port;

namespace birdcage {

// Real serial ports through libserialport, for standalone tools. libserialport cannot open ptys
// (codebases.md 3), so tests use FdTransport.
class SerialPortTransport final : public Transport {
public:
    static Result<std::unique_ptr<SerialPortTransport>> open(const std::string& path, int baud);

    Status write(std::string_view bytes, Deadline deadline) override;
    Result<std::size_t> read(char* buf, std::size_t n, Deadline deadline) override;
    void discard_input() override;

private:
    struct PortDeleter {
        void operator()(sp_port* port) const;
    };
    explicit SerialPortTransport(std::unique_ptr<sp_port, PortDeleter> port);

    std::unique_ptr<sp_port, PortDeleter> port_;
};

}  // namespace birdcage
