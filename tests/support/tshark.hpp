#pragma once
// Dissects a capture with tshark (Debian's package) and answers what the
// tests ask of it: how many EtherCAT frames, how many of them malformed
// (esc-facts.md §4), and arbitrary field values.

#include <filesystem>
#include <string>
#include <vector>

namespace ecpair::test {

struct TsharkResult {
    int exit_status = -1;
    std::vector<std::string> lines;  // stdout, one entry per line
};

// Runs `tshark -r FILE <arguments...>` and collects its output.
TsharkResult run_tshark(const std::filesystem::path& capture, const std::vector<std::string>& arguments);

// EtherCAT frames in the capture.
std::size_t count_ethercat_frames(const std::filesystem::path& capture);
// EtherCAT frames that tshark's dissector flags as malformed (_ws.malformed).
std::size_t count_malformed_ethercat_frames(const std::filesystem::path& capture);

}  // namespace ecpair::test
