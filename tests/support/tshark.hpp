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

// Captures EtherCAT frames on an interface of a namespace for `seconds`
// (tshark -i ... -a duration:N) into `file`. Returns tshark's exit status.
int capture(const std::string& netns, const std::string& interface, int seconds, const std::filesystem::path& file);

}  // namespace ecpair::test
