#pragma once
// One end of the master-to-master bridge, without the TAP device: frames go
// in with offer() (from the TAP reader) and come out of inbound() (for the
// TAP writer). It rides on the pair's frames through the redundancy
// controller's AcyclicMasterRedChannel seam:
//
//   ACTIVE   each cycle, after the CMF: DATA datagrams with our queued
//            frames and POLLs for the partner's, shared out by plan_slots();
//            as the copies come back (receive threads): the partner's
//            ANSWERs are delivered (the MAIN and the RED copy carry the same
//            answer: delivered once); next cycle, the copies that came back
//            in time are counted as answered or not.
//   INACTIVE as a POLL passes (on its first pass, before it is forwarded):
//            fill it with our queued frames; the other copy of the same
//            poll, arriving on the other adapter, gets the same answer (fill
//            once). After forwarding: deliver the ACTIVE's DATA once.
//            With the kernel path the program answers the polls, from
//            answers prepared here ahead (prepare_answers): the next one is
//            packed from the queue's head but the frames stay queued until
//            a poll took it, so an answer that no poll takes loses nothing.
//
// Delivery is in order and at most once per datagram: by the writer's
// session id and sequence number (a gap counts as lost). A datagram that
// does not decode is dropped and counted, never delivered.
//
// Threads: offer() on the TAP reader; inbound() drained by the TAP writer;
// the seam's calls on the cycle thread (ACTIVE) or the receive threads
// (returned() of the ACTIVE, everything of the INACTIVE; two at once). Queues and fill store are allocated at
// construction; every lock is held for a copy.

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/redundancy/acyclic_master_red_channel.hpp"
#include "ecpair/tap_bridge/bridge_datagram.hpp"
#include "ecpair/tap_bridge/frame_queue.hpp"
#include "ecpair/tap_bridge/slot_plan.hpp"

namespace ecpair::tap_bridge {

struct BridgeChannelOptions {
    std::uint32_t session = 1;                          // ours, distinct per start (TapBridge draws it at random)
    std::size_t poll_size = kMaxBridgeDatagramData;     // data bytes of the polls we send as ACTIVE
    std::size_t queue_frames = 256;                     // each way
    std::function<std::chrono::steady_clock::time_point()> clock = [] { return std::chrono::steady_clock::now(); };
};

struct BridgeCounters {
    std::uint64_t tx_frames = 0;  // our frames that left in a DATA or ANSWER datagram
    std::uint64_t tx_bytes = 0;
    std::uint64_t rx_frames = 0;  // the partner's frames delivered towards our TAP
    std::uint64_t rx_bytes = 0;
    std::uint64_t polls_sent = 0;        // ACTIVE
    std::uint64_t polls_answered = 0;    // ACTIVE: returned with the partner's answer
    std::uint64_t polls_unanswered = 0;  // ACTIVE: returned as sent (no partner bridge on the way)
    std::uint64_t answers_given = 0;     // INACTIVE: polls we filled (each poll once)
    std::uint64_t duplicates = 0;        // copies of a datagram already delivered (MAIN and RED): not a loss
    // Drops, by reason.
    std::uint64_t dropped_oversized = 0;       // a frame from the TAP larger than a datagram carries
    std::uint64_t dropped_tx_queue_full = 0;   // our queue towards the partner was full
    std::uint64_t dropped_rx_queue_full = 0;   // the queue towards our TAP was full
    std::uint64_t dropped_garbled = 0;         // bridge datagrams from the bus that did not decode
    std::uint64_t dropped_lost = 0;            // partner datagrams that never arrived (sequence gaps)
    std::uint64_t dropped_tap_write = 0;       // the TAP refused a frame (counted by TapBridge)
};

struct BridgeFlow {
    bool active = false;
    bool flowing = false;
    std::string why_not;  // when not flowing, for operators
};

class BridgeChannel final : public redundancy::AcyclicMasterRedChannel {
public:
    // Without a poll or answer for this long, status says the bridge is not flowing.
    static constexpr std::chrono::milliseconds kFlowTimeout{1000};

    explicit BridgeChannel(BridgeChannelOptions options);

    // ---- TAP side
    // A frame read from our TAP: queued for the partner, or dropped and counted.
    void offer(ConstBytes frame);
    // The partner's frames, for our TAP.
    FrameQueue& inbound() { return inbound_; }
    // Called after frames were queued inbound (on the thread that delivered them); must not block.
    void set_on_delivery(std::function<void()> callback) { on_delivery_ = std::move(callback); }
    void count_tap_write_failure() { counters_.dropped_tap_write.fetch_add(1, std::memory_order_relaxed); }

    BridgeCounters counters() const;
    BridgeFlow flow() const;
    std::size_t outbound_depth() const { return outbound_.depth(); }
    std::size_t inbound_depth() const { return inbound_.depth(); }
    std::size_t queue_capacity() const { return outbound_.capacity(); }
    std::uint32_t session() const { return options_.session; }

    // ---- redundancy::AcyclicMasterRedChannel
    void role_changed(bool active) override;
    void send_frames(master::FrameSender& sender, std::uint64_t cycle, std::size_t max_frames) override;
    void complete(std::uint16_t index, const master::ReturnedCopy& main_copy,
                  const master::ReturnedCopy& red_copy) override;
    void returned(master::LinkRole arrived_on, ConstBytes frame) override;
    void process(master::LinkRole arrived_on, wire::FrameView& frame, bool first_pass) override;
    void forwarded(master::LinkRole arrived_on, ConstBytes frame, bool first_pass) override;
    void kernel_forwarded(master::LinkRole arrived_on, ConstBytes frame,
                          redundancy::PreparedPollAnswers& answers) override;
    void prepare_answers(redundancy::PreparedPollAnswers& answers) override;

private:
    // What the INACTIVE wrote into one poll, for its other copy.
    struct Fill {
        std::uint32_t poll_session = 0;
        std::uint32_t poll_sequence = 0;
        bool used = false;
        std::size_t size = 0;
        std::array<std::uint8_t, kMaxBridgeDatagramData> data{};
    };
    static constexpr std::size_t kFills = 8;

    // INACTIVE, kernel path: what the channel put into one of the program's slots.
    struct PreparedAnswer {
        bool published = false;
        bool taken = false;  // a poll claimed it
        std::uint32_t sequence = 0;
        std::size_t frames = 0;  // from the queue's head, still queued until a poll takes them
        std::size_t bytes = 0;
        std::size_t size = 0;  // the poll size it answers
    };
    static constexpr std::size_t kMaxPreparedSlots = 8;

    // Sends one bridge datagram (data of `size` bytes in scratch_) as a frame of its own.
    void send_datagram(master::FrameSender& sender, std::uint16_t index, std::size_t size);
    // Packs queued frames while they fit; *head_too_large tells whether the
    // head frame fits not even the empty writer.
    std::size_t pack(BridgePayloadWriter& writer, bool* head_too_large = nullptr);
    // Kernel path: the answers polls took since the last look (their frames
    // leave the queue, oldest first), then the next answer in the next slot.
    void settle_taken(redundancy::PreparedPollAnswers& answers, std::size_t slots);
    void publish_next(redundancy::PreparedPollAnswers& answers, std::size_t slots, std::size_t poll_size);
    void answer(wire::DatagramView datagram, const BridgeHeader& poll);
    // Delivers a DATA or ANSWER datagram of the partner once; false if it was a duplicate.
    bool deliver(const BridgeDatagram& datagram);
    std::uint16_t backlog_bytes() const;
    void count_garbled(const BridgeError& error);
    std::int64_t now_ns() const;

    BridgeChannelOptions options_;
    FrameQueue outbound_;
    FrameQueue inbound_;
    std::function<void()> on_delivery_;
    std::atomic<bool> active_{false};
    std::atomic<std::uint32_t> tx_sequence_{0};

    // ACTIVE, cycle thread.
    std::array<std::uint8_t, kMaxBridgeDatagramData> scratch_{};
    std::uint32_t poll_sequence_ = 0;
    std::uint32_t cycles_since_data_ = 0;
    std::uint32_t cycles_since_poll_ = 0;
    std::atomic<std::size_t> partner_backlog_{0};  // written by the receive threads

    // INACTIVE, receive threads.
    std::mutex fill_mutex_;
    std::array<Fill, kFills> fills_{};
    std::size_t next_fill_ = 0;
    // INACTIVE, kernel path (under fill_mutex_ too).
    std::array<PreparedAnswer, kMaxPreparedSlots> prepared_{};
    std::size_t prepared_next_ = 0;  // the slot the program takes from
    bool prepared_stale_ = true;     // withdraw them all first (set at a role change)
    std::array<std::uint8_t, kMaxBridgeDatagramData> prepare_scratch_{};
    std::atomic<std::size_t> poll_size_{0};  // of the ACTIVE's last poll seen

    // Delivery (either role): the last sequence delivered per writer session.
    // A few sessions are remembered, so that frames of another writer (a
    // partner that restarted, a second ACTIVE) never make a session start
    // over and deliver its copies twice.
    struct RxSession {
        std::uint32_t session = 0;
        std::uint32_t last_sequence = 0;
        std::uint64_t last_used = 0;  // for replacing the least recently used
        bool used = false;
    };
    static constexpr std::size_t kRxSessions = 4;
    std::mutex rx_mutex_;
    std::array<RxSession, kRxSessions> rx_sessions_{};
    std::uint64_t rx_uses_ = 0;

    std::atomic<std::int64_t> last_exchange_ns_{0};  // ACTIVE: last answer; INACTIVE: last poll
    std::atomic<std::int64_t> role_since_ns_{0};

    struct AtomicCounters {
        std::atomic<std::uint64_t> tx_frames{0}, tx_bytes{0}, rx_frames{0}, rx_bytes{0}, polls_sent{0},
            polls_answered{0}, polls_unanswered{0}, answers_given{0}, duplicates{0}, dropped_oversized{0},
            dropped_tx_queue_full{0}, dropped_rx_queue_full{0}, dropped_garbled{0}, dropped_lost{0},
            dropped_tap_write{0};
    } counters_;
};

}  // namespace ecpair::tap_bridge
