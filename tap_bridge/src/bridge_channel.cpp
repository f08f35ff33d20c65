// BridgeChannel, frame by frame:
//
//   offer            TAP frame -> size check -> outbound queue
//   send_frames      plan_slots() -> DATA datagrams packed from the outbound
//   (ACTIVE)         queue, then POLLs of poll_size; one datagram per frame
//   returned         every frame back at the ACTIVE (receive threads):
//   (ACTIVE)         ANSWER -> deliver (once); our own DATA and POLLs -> nothing
//   complete         next cycle, the copies that came back in time: a poll
//   (ACTIVE)         answered, or returned as sent (unanswered)
//   process          POLL on its first pass -> answer(): the fill for this
//   (INACTIVE)       poll if the other copy made one, else a new one packed
//                    from the outbound queue; WKC + 1
//   forwarded        DATA on its first pass -> deliver (once)
//   (INACTIVE)
//   kernel_forwarded the frame as it arrived (the kernel forwarded it and
//   (INACTIVE,       answered its polls): DATA -> deliver; POLL -> its size,
//   kernel path)     then prepare_answers: settle the answers polls took
//                    (pop their frames), publish the next one
//   deliver          session/sequence check -> inbound queue -> on_delivery

#include "ecpair/tap_bridge/bridge_channel.hpp"

#include <algorithm>
#include <limits>

#include <fmt/format.h>

#include "ecpair/common/log.hpp"
#include "ecpair/wire/frame.hpp"
#include "tap_bridge_log.hpp"

namespace ecpair::tap_bridge {
namespace {

wire::DatagramHeader bridge_datagram_header() {
    wire::DatagramHeader h;
    h.command = wire::Command::Nop;
    h.address = wire::DatagramHeader::physical(0, kBridgeAdo);
    return h;
}

}  // namespace

BridgeChannel::BridgeChannel(BridgeChannelOptions options)
    : options_(std::move(options)), outbound_(options_.queue_frames), inbound_(options_.queue_frames) {
    options_.poll_size = std::clamp(options_.poll_size, kMinPollData, kMaxBridgeDatagramData);
    role_since_ns_.store(now_ns());
}

std::int64_t BridgeChannel::now_ns() const {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(options_.clock().time_since_epoch()).count();
}

void BridgeChannel::offer(ConstBytes frame) {
    if (frame.size() < kMinBridgedFrame || frame.size() > largest_frame(kMaxBridgeDatagramData)) {
        counters_.dropped_oversized.fetch_add(1, std::memory_order_relaxed);
        return;
    }
    if (!outbound_.push(frame)) counters_.dropped_tx_queue_full.fetch_add(1, std::memory_order_relaxed);
}

std::uint16_t BridgeChannel::backlog_bytes() const {
    const std::size_t bytes = outbound_.bytes() + outbound_.depth() * kFrameLengthPrefix;
    return static_cast<std::uint16_t>(std::min<std::size_t>(bytes, std::numeric_limits<std::uint16_t>::max()));
}

void BridgeChannel::role_changed(bool active) {
    if (active_.exchange(active) == active) return;
    {
        std::lock_guard lock(fill_mutex_);
        prepared_stale_ = true;
    }
    role_since_ns_.store(now_ns());
    last_exchange_ns_.store(0);
    partner_backlog_.store(0);
    cycles_since_data_ = 0;
    cycles_since_poll_ = 0;
    log()->info("bridge follows the role: {}", active ? "ACTIVE (sends DATA and POLLs after the CMF)"
                                                      : "INACTIVE (answers the ACTIVE's POLLs as it forwards them)");
}

std::size_t BridgeChannel::pack(BridgePayloadWriter& writer, bool* head_too_large) {
    std::size_t bytes = 0;
    outbound_.pop_while([&](ConstBytes frame) {
        if (!writer.add(frame)) {
            // Seen under the queue's lock: this frame fits not even an empty datagram of this size.
            if (head_too_large != nullptr) *head_too_large = writer.frame_count() == 0;
            return false;
        }
        bytes += frame.size();
        return true;
    });
    counters_.tx_frames.fetch_add(writer.frame_count(), std::memory_order_relaxed);
    counters_.tx_bytes.fetch_add(bytes, std::memory_order_relaxed);
    return writer.frame_count();
}

void BridgeChannel::send_datagram(master::FrameSender& sender, std::uint16_t index, std::size_t size) {
    wire::FrameBuilder builder(sender.buffer(), sender.ethernet());
    // One datagram of at most 1486 bytes always fits a frame.
    builder.append(bridge_datagram_header(), ConstBytes(scratch_.data(), size));
    sender.send(index, builder.finish());
}

void BridgeChannel::send_frames(master::FrameSender& sender, std::uint64_t, std::size_t max_frames) {
    SlotDemand demand;
    demand.slots = max_frames;
    demand.own_bytes = outbound_.bytes() + outbound_.depth() * kFrameLengthPrefix;
    demand.partner_bytes = partner_backlog_.load(std::memory_order_relaxed);
    demand.data_room = kMaxBridgePayload;
    demand.poll_room = options_.poll_size - kBridgeHeaderSize;
    demand.cycles_since_data = cycles_since_data_;
    demand.cycles_since_poll = cycles_since_poll_;
    SlotPlan plan = plan_slots(demand);

    std::uint16_t index = 0;
    std::size_t data_sent = 0;
    for (; data_sent < plan.data; ++data_sent) {
        BridgePayloadWriter writer(scratch_);
        if (pack(writer) == 0) break;
        const auto size = writer.seal(BridgeKind::Data, options_.session, tx_sequence_.fetch_add(1) + 1, backlog_bytes());
        send_datagram(sender, index++, size);
    }
    // Frames the plan gave to data but the queue did not need go to polls.
    const std::size_t polls = plan.polls + (plan.data - data_sent);
    for (std::size_t i = 0; i < polls; ++i) {
        BridgePayloadWriter writer(Bytes(scratch_.data(), options_.poll_size));
        writer.seal(BridgeKind::Poll, options_.session, ++poll_sequence_, 0);
        send_datagram(sender, index++, options_.poll_size);
    }
    counters_.polls_sent.fetch_add(polls, std::memory_order_relaxed);
    cycles_since_data_ = data_sent > 0 ? 0 : cycles_since_data_ + 1;
    cycles_since_poll_ = polls > 0 ? 0 : cycles_since_poll_ + 1;
}

void BridgeChannel::count_garbled(const BridgeError& error) {
    const auto n = counters_.dropped_garbled.fetch_add(1, std::memory_order_relaxed);
    if (n == 0) {
        log()->warn("{}: dropped (the first; later ones are counted in dropped_garbled)", error.describe());
    } else {
        log()->debug("{}: dropped", error.describe());
    }
}

void BridgeChannel::returned(master::LinkRole, ConstBytes frame) {
    auto view = wire::ConstFrameView::parse(frame);
    if (!view) return;
    for (const auto d : *view) {
        if (!is_bridge_datagram(d)) continue;
        const auto data = d.data();
        // Our own DATA and POLLs come back too; only what the partner wrote matters here.
        const auto kind = peek_kind(data);
        if (!kind || *kind == BridgeKind::Data || *kind == BridgeKind::Poll) continue;
        const auto decoded = decode_bridge_datagram(data, d.frame_offset() + wire::kDatagramHeaderSize);
        if (!decoded) {
            count_garbled(decoded.error());
            continue;
        }
        partner_backlog_.store(decoded->header.backlog, std::memory_order_relaxed);
        last_exchange_ns_.store(now_ns(), std::memory_order_relaxed);
        deliver(*decoded);
    }
}

void BridgeChannel::complete(std::uint16_t, const master::ReturnedCopy& main_copy, const master::ReturnedCopy& red_copy) {
    // What it carried was delivered by returned() as it arrived; here only the count.
    bool answered = false;
    bool unanswered = false;
    for (const auto* copy : {&main_copy, &red_copy}) {
        if (copy->path == master::CopyPath::Missing) continue;
        auto view = wire::ConstFrameView::parse(copy->frame);
        if (!view) continue;
        for (const auto d : *view) {
            if (!is_bridge_datagram(d)) continue;
            const auto kind = peek_kind(d.data());
            answered = answered || kind == BridgeKind::Answer;
            unanswered = unanswered || kind == BridgeKind::Poll;
        }
    }
    if (answered) {
        counters_.polls_answered.fetch_add(1, std::memory_order_relaxed);
    } else if (unanswered) {
        counters_.polls_unanswered.fetch_add(1, std::memory_order_relaxed);
    }
}

bool BridgeChannel::deliver(const BridgeDatagram& datagram) {
    const BridgeHeader& h = datagram.header;
    if (h.frame_count == 0) return false;  // an empty answer: nothing to deliver, no sequence used
    std::size_t delivered = 0;
    {
        std::lock_guard lock(rx_mutex_);
        auto it = std::find_if(rx_sessions_.begin(), rx_sessions_.end(),
                               [&](const RxSession& r) { return r.used && r.session == h.session; });
        if (it == rx_sessions_.end()) {
            // A writer not heard from lately (the partner restarted): it starts here.
            it = std::min_element(rx_sessions_.begin(), rx_sessions_.end(), [](const RxSession& a, const RxSession& b) {
                return a.used != b.used ? !a.used : a.last_used < b.last_used;
            });
            *it = RxSession{h.session, h.sequence - 1, 0, true};
        }
        it->last_used = ++rx_uses_;
        const auto ahead = static_cast<std::int32_t>(h.sequence - it->last_sequence);
        if (ahead <= 0) {
            counters_.duplicates.fetch_add(1, std::memory_order_relaxed);
            return false;
        }
        if (ahead > 1) counters_.dropped_lost.fetch_add(static_cast<std::uint64_t>(ahead - 1), std::memory_order_relaxed);
        it->last_sequence = h.sequence;
        datagram.for_each_frame([&](ConstBytes frame) {
            if (!inbound_.push(frame)) {
                counters_.dropped_rx_queue_full.fetch_add(1, std::memory_order_relaxed);
                return;
            }
            ++delivered;
            counters_.rx_frames.fetch_add(1, std::memory_order_relaxed);
            counters_.rx_bytes.fetch_add(frame.size(), std::memory_order_relaxed);
        });
    }
    if (delivered > 0 && on_delivery_) on_delivery_();
    return true;
}

void BridgeChannel::answer(wire::DatagramView datagram, const BridgeHeader& poll) {
    const Bytes data = datagram.data();
    std::lock_guard lock(fill_mutex_);
    const auto same_poll = [&](const Fill& f) {
        return f.used && f.poll_session == poll.session && f.poll_sequence == poll.sequence && f.size == data.size();
    };
    if (const auto it = std::find_if(fills_.begin(), fills_.end(), same_poll); it != fills_.end()) {
        std::copy_n(it->data.begin(), it->size, data.begin());  // the other copy of a poll already answered
    } else {
        BridgePayloadWriter writer(data);
        bool head_too_large = false;
        pack(writer, &head_too_large);
        if (head_too_large) {
            // The head frame does not fit even an empty poll of this size (the
            // partner polls with less room than our MTU): it would block the queue.
            // While INACTIVE only holders of fill_mutex_ take from the queue: the head is still that frame.
            outbound_.drop_head();
            counters_.dropped_oversized.fetch_add(1, std::memory_order_relaxed);
            pack(writer);
        }
        const std::uint32_t sequence = writer.frame_count() > 0 ? tx_sequence_.fetch_add(1) + 1 : tx_sequence_.load();
        writer.seal(BridgeKind::Answer, options_.session, sequence, backlog_bytes());
        Fill& fill = fills_[next_fill_];
        next_fill_ = (next_fill_ + 1) % fills_.size();
        fill.used = true;
        fill.poll_session = poll.session;
        fill.poll_sequence = poll.sequence;
        fill.size = data.size();
        std::copy(data.begin(), data.end(), fill.data.begin());
        counters_.answers_given.fetch_add(1, std::memory_order_relaxed);
    }
    datagram.set_wkc(static_cast<std::uint16_t>(datagram.wkc() + 1));
    last_exchange_ns_.store(now_ns(), std::memory_order_relaxed);
}

void BridgeChannel::process(master::LinkRole, wire::FrameView& frame, bool first_pass) {
    if (!first_pass) return;
    for (auto d : frame) {
        if (!is_bridge_datagram(d)) continue;
        const auto data = d.data();
        if (peek_kind(data) != BridgeKind::Poll) continue;
        const auto decoded = decode_bridge_datagram(data, d.frame_offset() + wire::kDatagramHeaderSize);
        if (!decoded) {
            count_garbled(decoded.error());  // forwarded() skips POLLs: counted once
            continue;
        }
        answer(d, decoded->header);
    }
}

void BridgeChannel::forwarded(master::LinkRole, ConstBytes frame, bool first_pass) {
    if (!first_pass) return;
    auto view = wire::ConstFrameView::parse(frame);
    if (!view) return;
    for (const auto d : *view) {
        if (!is_bridge_datagram(d)) continue;
        const auto data = d.data();
        // POLLs were handled (answered or counted) before the frame left.
        if (const auto kind = peek_kind(data); kind == BridgeKind::Poll || kind == BridgeKind::Answer) continue;
        const auto decoded = decode_bridge_datagram(data, d.frame_offset() + wire::kDatagramHeaderSize);
        if (!decoded) {
            count_garbled(decoded.error());
            continue;
        }
        if (decoded->header.kind == BridgeKind::Data) deliver(*decoded);
    }
}

void BridgeChannel::kernel_forwarded(master::LinkRole arrived_on, ConstBytes frame,
                                     redundancy::PreparedPollAnswers& answers) {
    forwarded(arrived_on, frame, true);  // the ACTIVE's DATA; it skips the polls
    auto view = wire::ConstFrameView::parse(frame);
    if (!view) return;
    bool polled = false;
    for (const auto d : *view) {
        if (!is_bridge_datagram(d)) continue;
        const auto data = d.data();
        if (peek_kind(data) != BridgeKind::Poll) continue;
        if (const auto decoded = decode_bridge_datagram(data, d.frame_offset() + wire::kDatagramHeaderSize); !decoded) {
            count_garbled(decoded.error());
            continue;
        }
        poll_size_.store(data.size(), std::memory_order_relaxed);
        last_exchange_ns_.store(now_ns(), std::memory_order_relaxed);
        polled = true;
    }
    if (polled) prepare_answers(answers);
}

void BridgeChannel::prepare_answers(redundancy::PreparedPollAnswers& answers) {
    const std::size_t poll_size = poll_size_.load(std::memory_order_relaxed);
    std::lock_guard lock(fill_mutex_);
    const std::size_t slots = std::min(answers.slots(), prepared_.size());
    if (slots == 0 || active_.load()) return;
    if (prepared_stale_) {
        answers.withdraw_all();
        prepared_ = {};
        prepared_next_ = 0;
        prepared_stale_ = false;
    }
    if (poll_size == 0) return;  // no poll seen yet: the size to answer is not known
    settle_taken(answers, slots);
    const PreparedAnswer& waiting = prepared_[prepared_next_];
    const bool still_right = waiting.frames > 0 ? waiting.sequence == tx_sequence_.load() + 1 : outbound_.depth() == 0;
    if (waiting.published && !waiting.taken && waiting.size == poll_size && still_right) return;
    publish_next(answers, slots, poll_size);
}

void BridgeChannel::settle_taken(redundancy::PreparedPollAnswers& answers, std::size_t slots) {
    // Oldest first: the slot after the newest was published longest ago.
    for (std::size_t k = 1; k <= slots; ++k) {
        const std::size_t slot = (prepared_next_ + k) % slots;
        PreparedAnswer& p = prepared_[slot];
        if (!p.published || p.taken || answers.claimed_by(slot) == 0) continue;
        p.taken = true;
        counters_.answers_given.fetch_add(1, std::memory_order_relaxed);
        // An answer prepared again (a new poll size) carries the sequence of
        // the one before: whichever a poll took first, its frames left once.
        if (p.frames == 0 || p.sequence != tx_sequence_.load() + 1) continue;
        outbound_.pop_while([](ConstBytes) { return true; }, p.frames);
        tx_sequence_.store(p.sequence);
        counters_.tx_frames.fetch_add(p.frames, std::memory_order_relaxed);
        counters_.tx_bytes.fetch_add(p.bytes, std::memory_order_relaxed);
    }
}

void BridgeChannel::publish_next(redundancy::PreparedPollAnswers& answers, std::size_t slots, std::size_t poll_size) {
    const Bytes data(prepare_scratch_.data(), poll_size);
    BridgePayloadWriter writer(data);
    std::size_t bytes = 0;
    for (;;) {
        writer = BridgePayloadWriter(data);
        bytes = 0;
        bool head_too_large = false;
        outbound_.peek_while([&](ConstBytes frame) {
            if (!writer.add(frame)) {
                head_too_large = writer.frame_count() == 0;
                return false;
            }
            bytes += frame.size();
            return true;
        });
        if (!head_too_large) break;
        // As in answer(): a head frame larger than the partner's polls would block the queue.
        outbound_.drop_head();
        counters_.dropped_oversized.fetch_add(1, std::memory_order_relaxed);
    }
    const std::size_t frames = writer.frame_count();
    const std::uint32_t sequence = tx_sequence_.load() + (frames > 0 ? 1 : 0);
    // The backlog after this answer: its frames are still queued.
    const std::size_t queued = outbound_.bytes() + outbound_.depth() * kFrameLengthPrefix;
    const std::size_t taken = bytes + frames * kFrameLengthPrefix;
    const auto backlog = static_cast<std::uint16_t>(
        std::min<std::size_t>(queued > taken ? queued - taken : 0, std::numeric_limits<std::uint16_t>::max()));
    writer.seal(BridgeKind::Answer, options_.session, sequence, backlog);
    const std::size_t slot = (prepared_next_ + 1) % slots;
    answers.publish(slot, data);
    prepared_[slot] = PreparedAnswer{true, false, sequence, frames, bytes, poll_size};
    prepared_next_ = slot;
}

BridgeCounters BridgeChannel::counters() const {
    const auto& c = counters_;
    BridgeCounters s;
    s.tx_frames = c.tx_frames.load();
    s.tx_bytes = c.tx_bytes.load();
    s.rx_frames = c.rx_frames.load();
    s.rx_bytes = c.rx_bytes.load();
    s.polls_sent = c.polls_sent.load();
    s.polls_answered = c.polls_answered.load();
    s.polls_unanswered = c.polls_unanswered.load();
    s.answers_given = c.answers_given.load();
    s.duplicates = c.duplicates.load();
    s.dropped_oversized = c.dropped_oversized.load();
    s.dropped_tx_queue_full = c.dropped_tx_queue_full.load();
    s.dropped_rx_queue_full = c.dropped_rx_queue_full.load();
    s.dropped_garbled = c.dropped_garbled.load();
    s.dropped_lost = c.dropped_lost.load();
    s.dropped_tap_write = c.dropped_tap_write.load();
    return s;
}

BridgeFlow BridgeChannel::flow() const {
    BridgeFlow f;
    f.active = active_.load();
    const std::int64_t last = last_exchange_ns_.load();
    const std::int64_t now = now_ns();
    const std::int64_t timeout = std::chrono::duration_cast<std::chrono::nanoseconds>(kFlowTimeout).count();
    f.flowing = last != 0 && now - last <= timeout;
    if (f.flowing) return f;
    const auto ago = [&](std::int64_t since) { return fmt::format("{:.1f} s", static_cast<double>(now - since) / 1e9); };
    if (f.active) {
        f.why_not = last == 0 ? fmt::format("no partner answers our polls (ACTIVE for {}): is the INACTIVE running "
                                            "with a tap block?", ago(role_since_ns_.load()))
                              : fmt::format("the partner stopped answering our polls {} ago", ago(last));
    } else {
        f.why_not = last == 0 ? fmt::format("no ACTIVE master polls the bridge (INACTIVE for {}): frames wait in the "
                                            "queue, then drop",
                                            ago(role_since_ns_.load()))
                              : fmt::format("no poll from an ACTIVE master for {}", ago(last));
    }
    return f;
}

}  // namespace ecpair::tap_bridge
