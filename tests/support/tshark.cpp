#include "tshark.hpp"

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace ecpair::test {
namespace {

std::string quoted(const std::string& word) {
    std::string out = "'";
    for (const char c : word) {
        if (c == '\'') {
            out += "'\\''";
        } else {
            out += c;
        }
    }
    return out + "'";
}

}  // namespace

TsharkResult run_tshark(const std::filesystem::path& capture, const std::vector<std::string>& arguments) {
    std::string command = "tshark -r " + quoted(capture.string());
    for (const auto& a : arguments) command += " " + quoted(a);
    command += " 2>/dev/null";
    FILE* pipe = ::popen(command.c_str(), "r");
    if (pipe == nullptr) throw std::runtime_error("cannot run: " + command);
    TsharkResult result;
    std::array<char, 4096> buffer{};
    std::string line;
    while (std::fgets(buffer.data(), static_cast<int>(buffer.size()), pipe) != nullptr) {
        line += buffer.data();
        if (!line.empty() && line.back() == '\n') {
            line.pop_back();
            result.lines.push_back(line);
            line.clear();
        }
    }
    if (!line.empty()) result.lines.push_back(line);
    const int status = ::pclose(pipe);
    result.exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
}

std::size_t count_ethercat_frames(const std::filesystem::path& capture) {
    const auto r = run_tshark(capture, {"-Y", "eth.type == 0x88a4 || ecatf", "-T", "fields", "-e", "frame.number"});
    if (r.exit_status != 0) throw std::runtime_error("tshark failed on " + capture.string());
    return r.lines.size();
}

std::size_t count_malformed_ethercat_frames(const std::filesystem::path& capture) {
    const auto r = run_tshark(capture, {"-Y", "(eth.type == 0x88a4 || ecatf) && _ws.malformed", "-T", "fields", "-e",
                                        "frame.number"});
    if (r.exit_status != 0) throw std::runtime_error("tshark failed on " + capture.string());
    return r.lines.size();
}

int capture(const std::string& netns, const std::string& interface, int seconds, const std::filesystem::path& file) {
    const std::string command = "ip netns exec " + quoted(netns) + " tshark -q -i " + quoted(interface) +
                                " -f 'ether proto 0x88a4' -a duration:" + std::to_string(seconds) + " -w " +
                                quoted(file.string()) + " >/dev/null 2>&1";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace ecpair::test
