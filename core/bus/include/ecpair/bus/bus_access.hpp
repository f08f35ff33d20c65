#pragma once
// Synchronous datagram exchange with the slaves: send one datagram, get it
// back with its data and working counter. Scans, SII reads and InitCmds are
// written against this interface, so the same code runs over a plain link
// (ecpairctl scan) and, inside the master, through the acyclic queue of the
// cycle thread (the caller then blocks on a worker thread, never the cycle).

#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "ecpair/common/expected.hpp"
#include "ecpair/wire/command.hpp"
#include "ecpair/wire/datagram.hpp"

namespace ecpair::bus {

struct DatagramRequest {
    wire::Command command = wire::Command::Nop;
    std::uint32_t address = 0;       // ADP|ADO<<16, or the logical address
    std::vector<std::uint8_t> data;  // written data, or zeros of the length to read
    std::chrono::milliseconds timeout{100};  // per attempt
    std::uint32_t retries = 2;               // further attempts after a timeout
};

struct DatagramReply {
    std::vector<std::uint8_t> data;
    std::uint16_t wkc = 0;
    // The IRQ field as it came back: the ECAT events (0x0210 AND the mask
    // 0x0200) of the slaves it passed, ORed.
    std::uint16_t irq = 0;
};

enum class BusErrc : std::uint8_t {
    Timeout,               // no answer after every attempt
    LinkFailure,           // the link refused to send
    MasterRedStateInactive,  // the master is INACTIVE and must not talk to slaves
    InvalidRequest,        // the request cannot be put on the wire (too long...)
    Cancelled,             // the master shut down or changed role while waiting
};

struct BusError {
    BusErrc code;
    std::string message;
};

std::string_view to_string(BusErrc code);

class BusAccess {
public:
    virtual ~BusAccess() = default;
    virtual Expected<DatagramReply, BusError> exchange(const DatagramRequest& request) = 0;
    // Datagrams whose answers do not depend on each other, replies in request
    // order. This default exchanges them one after the other; the master's
    // acyclic queue sends them together and wakes the caller once.
    virtual std::vector<Expected<DatagramReply, BusError>> exchange_all(std::span<const DatagramRequest> requests);
    // Why every request would be refused now (the master is INACTIVE, shutting
    // down), nullopt while requests are taken: lets a caller refuse its own
    // request at once instead of queuing it.
    virtual std::optional<BusErrc> refusal() const { return std::nullopt; }
};

// How a single slave is addressed: by ring position (APxx) or by its
// configured station address (FPxx).
struct SlaveAddress {
    enum class Mode : std::uint8_t { Position, Station };
    Mode mode = Mode::Position;
    std::uint16_t value = 0;

    static SlaveAddress position(std::uint16_t p) { return {Mode::Position, p}; }
    static SlaveAddress station(std::uint16_t s) { return {Mode::Station, s}; }
    // The ADP to put on the wire: -position for auto-increment, the address itself otherwise.
    std::uint16_t adp() const {
        return mode == Mode::Position ? static_cast<std::uint16_t>(0x10000u - value) : value;
    }
    wire::Command read_command() const { return mode == Mode::Position ? wire::Command::Aprd : wire::Command::Fprd; }
    wire::Command write_command() const { return mode == Mode::Position ? wire::Command::Apwr : wire::Command::Fpwr; }
    std::string to_string() const;
};

// The request that reads `length` bytes at `ado` of one slave.
DatagramRequest read_request(SlaveAddress slave, std::uint16_t ado, std::size_t length);
// Reads `length` bytes at `ado` of one slave. A reply with WKC 0 (nobody
// answered) is returned as is: callers decide what a missing slave means.
Expected<DatagramReply, BusError> read_register(BusAccess& bus, SlaveAddress slave, std::uint16_t ado,
                                                std::size_t length);
Expected<DatagramReply, BusError> write_register(BusAccess& bus, SlaveAddress slave, std::uint16_t ado,
                                                 std::vector<std::uint8_t> data);

}  // namespace ecpair::bus
