#pragma once
// The ACTIVE's side of the Cyclic Master Red Frame: every cycle, after the
// cyclic slave frames, write() turns this cycle's CmfContent into the
// plan's frames and hands each to the master's FrameSender, which sends it
// on MAIN and on RED. Runs on the cycle thread: everything it needs is sized
// in the constructor, write() allocates nothing.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "ecpair/common/expected.hpp"
#include "ecpair/master/cycle_extension.hpp"
#include "ecpair/redundancy/cmf_format.hpp"

namespace ecpair::redundancy {

// Why write() sent nothing: the content does not match the layout the
// writer was made for, or the sender's buffer cannot hold a frame.
struct CmfWriteError {
    enum class What : std::uint8_t { SlaveCount, ShadowInputsSize, MasterPdOutSize, SenderBufferTooSmall };
    What what = What::SlaveCount;
    std::size_t expected = 0;
    std::size_t actual = 0;

    std::string describe() const;  // "CMF content has 3 slaves, the layout 4"
};

class CmfWriter {
public:
    explicit CmfWriter(CmfPlan plan);

    const CmfPlan& plan() const { return plan_; }

    // Builds the frames of one cycle and sends frame i with sender.send(i, ...).
    // content.master_pd_in is not read: the writer reserves that section as
    // zeros for the INACTIVE to fill. Returns the number of frames sent.
    Expected<std::size_t, CmfWriteError> write(const CmfContent& content, master::FrameSender& sender);

private:
    Expected<void, CmfWriteError> check(const CmfContent& content, std::size_t buffer_size,
                                        std::size_t ethernet_header_size) const;
    void encode_sections(const CmfContent& content);
    ConstBytes section(const CmfContent& content, CmfKind kind) const;

    CmfPlan plan_;
    std::array<std::uint8_t, CmfHeader::kSize> header_bytes_{};
    std::vector<std::uint8_t> slave_bytes_;  // slave_count entries
};

}  // namespace ecpair::redundancy
