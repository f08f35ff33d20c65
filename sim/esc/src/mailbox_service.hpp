#pragma once
// The PDI side of the mailbox: what the slave stack does with SM0/SM1 after
// each frame while the mailbox runs (PREOP, SAFEOP, OP, BOOT):
//
//  - the master completed reading SM1: tell the handler (it may post more);
//  - the master completed writing SM0: hand the buffer to the handler, then
//    free SM0 (the stack has read it);
//  - the master toggled SM1's repeat request: write the last reply again and
//    acknowledge (datasheet I §8.6).
//
// It is also the handler's MailboxOutbox. The reply copy kept for repeats is
// allocated once, as large as the largest described SM1.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "ecpair/sim/mailbox.hpp"
#include "esc_memory.hpp"
#include "sync_manager.hpp"

namespace ecpair::sim {

class MailboxService final : public MailboxOutbox {
public:
    MailboxService(EscMemory& memory, SyncManagerUnit& sync_managers, std::size_t reply_capacity);

    void set_handler(std::unique_ptr<MailboxHandler> handler);
    // The stack starts or stops the mailbox with the AL state.
    void set_running(bool running);
    bool running() const { return running_; }
    void after_frame();

    bool post(ConstBytes reply) override;
    bool full() const override;

private:
    bool channels_ready() const;
    void write_reply(ConstBytes reply);

    EscMemory& memory_;
    SyncManagerUnit& sync_managers_;
    std::unique_ptr<MailboxHandler> handler_;
    std::vector<std::uint8_t> last_reply_;
    std::size_t last_reply_size_ = 0;
    bool running_ = false;
};

}  // namespace ecpair::sim
