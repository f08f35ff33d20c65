#pragma once
// The FoE server of an emulated slave (ETG.1000.6 §5.8): the slave's half of
// the FoE state machine over a small file store of its own
// (docs/ESC_EMULATION.md "FoE server").
//
//   Idle     RRQ(password, name): a wrong password -> ERR 0x800A (no rights),
//            no such file -> ERR 0x8001; else DATA(1) and Reading.
//            WRQ(password, name): a wrong password -> ERR 0x800A, a name
//            that is empty -> ERR 0x8004; else ACK(0) and Writing.
//   Reading  ACK(n) of the packet just sent: the next DATA, or Idle after
//            the last one (shorter than a full packet; an empty one when
//            the file fills its last packet exactly).
//   Writing  DATA(n) with the next number: stored and ACK(n); a short one
//            ends the file (it replaces one of that name) and Idle. While
//            the slave is "busy" (busy_packets), a DATA is answered BUSY
//            and not taken: the master sends it again. A file that grows
//            past the store's room -> ERR 0x8003 (disk full).
//   any      ERR from the master: back to Idle. A packet number out of
//            order -> ERR 0x8005; a message that makes no sense now ->
//            ERR 0x8004 (illegal); both back to Idle.
// The password (0: none asked) guards reads and writes alike. FoE runs in
// PREOP, SAFEOP, OP and BOOT.

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/sim/mailbox_server.hpp"
#include "ecpair/wire/foe.hpp"

namespace ecpair::sim {

class FoeServer final : public MailboxProtocol {
public:
    static constexpr std::size_t kDefaultRoom = 4u << 20;  // bytes of files a slave keeps

    // `mailbox_out_size`: SM0's length (the longest DATA the master can
    // write); `mailbox_in_size`: SM1's (the longest the slave sends).
    FoeServer(std::size_t mailbox_out_size, std::size_t mailbox_in_size, std::size_t room = kDefaultRoom);

    wire::MailboxType type() const override { return wire::MailboxType::FoE; }
    bool serves_in(eni::SlaveState state) const override { return state != eni::SlaveState::Init; }
    void on_request(ConstBytes body, MailboxReplies& replies) override;
    void reset() override;

    // ---- the slave's side (ecsim ctl, tests)
    void set_password(std::uint32_t password) { password_ = password; }
    // The next `packets` DATA packets of a write are answered BUSY.
    void set_busy_packets(std::uint32_t packets) { busy_packets_ = packets; }
    const std::map<std::string, std::vector<std::uint8_t>>& files() const { return files_; }
    void put_file(const std::string& name, std::vector<std::uint8_t> data) { files_[name] = std::move(data); }

private:
    enum class State : std::uint8_t { Idle, Reading, Writing };

    void on_read_request(const wire::FoeReadRequest& request, MailboxReplies& replies);
    void on_write_request(const wire::FoeWriteRequest& request, MailboxReplies& replies);
    void on_ack(const wire::FoeAck& ack, MailboxReplies& replies);
    void on_data(const wire::FoeData& data, MailboxReplies& replies);
    void send_data(MailboxReplies& replies);
    void fail(std::uint32_t code, const std::string& text, MailboxReplies& replies);
    std::size_t stored_bytes() const;

    std::size_t out_packet_;  // the most a DATA from the master carries
    std::size_t in_packet_;   // the most a DATA to the master carries
    std::size_t room_;
    std::uint32_t password_ = 0;
    std::uint32_t busy_packets_ = 0;
    std::map<std::string, std::vector<std::uint8_t>> files_;

    State state_ = State::Idle;
    std::string file_;                // the file being read or written
    std::vector<std::uint8_t> data_;  // Writing: what came so far
    std::size_t offset_ = 0;          // Reading: bytes sent before the packet in flight
    std::size_t in_flight_ = 0;       // Reading: bytes of the packet in flight
    std::uint32_t packet_ = 0;        // the packet sent (Reading) or acknowledged (Writing) last
};

}  // namespace ecpair::sim
