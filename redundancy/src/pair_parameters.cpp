// PairParameters: the byte-exact encoding that the CMF header carries and
// the fingerprint is computed over, and the readable list of differences
// the INACTIVE logs when its partner was configured differently.

#include "ecpair/redundancy/pair_parameters.hpp"

#include <array>

#include <fmt/format.h>

namespace ecpair::redundancy {
namespace {

constexpr std::uint8_t kCableRedundancyBit = 0x01;
constexpr std::uint8_t kSplitLrwBit = 0x02;
constexpr std::uint8_t kUpdateSlavePdInBit = 0x04;
constexpr std::uint8_t kUpdateSlavePdOutBit = 0x08;

constexpr std::uint64_t kFnvOffsetBasis = 0xcbf29ce484222325ull;
constexpr std::uint64_t kFnvPrime = 0x100000001b3ull;

std::uint8_t flag(bool on, std::uint8_t bit) { return on ? bit : std::uint8_t{0}; }

// "1000 µs", "62.5 µs".
std::string microseconds(std::chrono::nanoseconds t) {
    const auto ns = t.count();
    if (ns % 1000 == 0) return fmt::format("{} µs", ns / 1000);
    std::string text = fmt::format("{:.3f}", static_cast<double>(ns) / 1000.0);
    while (text.back() == '0') text.pop_back();
    return text + " µs";
}

std::string on_off(bool on) { return on ? "on" : "off"; }

}  // namespace

void PairParameters::encode(Bytes out) const {
    store_le<std::uint64_t>(out, 0, eni_content_hash);
    store_le<std::uint64_t>(out, 8, static_cast<std::uint64_t>(cycle_time.count()));
    store_le<std::uint32_t>(out, 16, master_pd_out_size);
    store_le<std::uint32_t>(out, 20, master_pd_in_size);
    store_le<std::uint16_t>(out, 24, max_acyc_frames_per_cycle);
    out[26] = static_cast<std::uint8_t>(flag(cable_redundancy, kCableRedundancyBit) | flag(split_lrw, kSplitLrwBit) |
                                        flag(update_slave_pd_in, kUpdateSlavePdInBit) |
                                        flag(update_slave_pd_out, kUpdateSlavePdOutBit));
    out[27] = 0;
}

PairParameters PairParameters::decode(ConstBytes in) {
    PairParameters p;
    p.eni_content_hash = load_le<std::uint64_t>(in, 0);
    p.cycle_time = std::chrono::nanoseconds(static_cast<std::int64_t>(load_le<std::uint64_t>(in, 8)));
    p.master_pd_out_size = load_le<std::uint32_t>(in, 16);
    p.master_pd_in_size = load_le<std::uint32_t>(in, 20);
    p.max_acyc_frames_per_cycle = load_le<std::uint16_t>(in, 24);
    const std::uint8_t flags = in[26];
    p.cable_redundancy = (flags & kCableRedundancyBit) != 0;
    p.split_lrw = (flags & kSplitLrwBit) != 0;
    p.update_slave_pd_in = (flags & kUpdateSlavePdInBit) != 0;
    p.update_slave_pd_out = (flags & kUpdateSlavePdOutBit) != 0;
    return p;
}

std::uint64_t PairParameters::fingerprint() const {
    std::array<std::uint8_t, kEncodedSize> bytes{};
    encode(bytes);
    std::uint64_t hash = kFnvOffsetBasis;
    for (const std::uint8_t b : bytes) {
        hash ^= b;
        hash *= kFnvPrime;
    }
    return hash;
}

std::vector<std::string> differences(const PairParameters& ours, const PairParameters& theirs) {
    std::vector<std::string> found;
    if (ours.eni_content_hash != theirs.eni_content_hash) {
        found.push_back(
            fmt::format("ENI (content hash {:#018x} vs {:#018x})", ours.eni_content_hash, theirs.eni_content_hash));
    }
    if (ours.cycle_time != theirs.cycle_time) {
        found.push_back(fmt::format("cycle time {} vs {}", microseconds(ours.cycle_time), microseconds(theirs.cycle_time)));
    }
    if (ours.cable_redundancy != theirs.cable_redundancy) {
        found.push_back(
            fmt::format("cable redundancy {} vs {}", on_off(ours.cable_redundancy), on_off(theirs.cable_redundancy)));
    }
    if (ours.split_lrw != theirs.split_lrw) {
        found.push_back(fmt::format("split LRW {} vs {}", on_off(ours.split_lrw), on_off(theirs.split_lrw)));
    }
    if (ours.master_pd_out_size != theirs.master_pd_out_size) {
        found.push_back(fmt::format("master PD out size {} vs {} bytes", ours.master_pd_out_size,
                                    theirs.master_pd_out_size));
    }
    if (ours.master_pd_in_size != theirs.master_pd_in_size) {
        found.push_back(
            fmt::format("master PD in size {} vs {} bytes", ours.master_pd_in_size, theirs.master_pd_in_size));
    }
    if (ours.update_slave_pd_in != theirs.update_slave_pd_in) {
        found.push_back(fmt::format("update slave PD in {} vs {}", on_off(ours.update_slave_pd_in),
                                    on_off(theirs.update_slave_pd_in)));
    }
    if (ours.update_slave_pd_out != theirs.update_slave_pd_out) {
        found.push_back(fmt::format("update slave PD out {} vs {}", on_off(ours.update_slave_pd_out),
                                    on_off(theirs.update_slave_pd_out)));
    }
    if (ours.max_acyc_frames_per_cycle != theirs.max_acyc_frames_per_cycle) {
        found.push_back(fmt::format("max acyclic frames per cycle {} vs {}", ours.max_acyc_frames_per_cycle,
                                    theirs.max_acyc_frames_per_cycle));
    }
    return found;
}

}  // namespace ecpair::redundancy
