// ecsim: a simulated EtherCAT slave segment on real network interfaces.
//
// Start-up, in order: parse the command line (exit 2 on bad usage), block
// SIGINT/SIGTERM and take them through a signalfd (so the event loop sees
// them as a readable fd and exits cleanly, flushing the pcap file), load the
// ENI and build the segment from its slaves, open the MAIN (and RED)
// interface and the carrier monitor, open the pcap file, listen on the
// control socket, then run the event loop (segment_runner.hpp). Any failure
// on the way is logged and exits with status 1.
//
// `ecsim ctl ...` is the client of the control socket instead (control_client.hpp).

#include <signal.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <memory>
#include <system_error>
#include <variant>

#include "command_line.hpp"
#include "control_client.hpp"
#include "ecpair/common/log.hpp"
#include "ecpair/common/realtime.hpp"
#include "ecpair/eni/loader.hpp"
#include "ecpair/link/link_admin.hpp"
#include "ecpair/link/link_state_monitor.hpp"
#include "ecpair/link/pcap_link.hpp"
#include "segment_runner.hpp"

namespace ecpair::ecsim {
namespace {

spdlog::logger& main_log() {
    static const auto logger = ecpair::logger("ecsim");
    return *logger;
}

int fail(const std::string& message) {
    main_log().error("{}", message);
    return kExitFailure;
}

// SIGINT and SIGTERM, blocked and delivered through the returned fd.
int open_stop_signals() {
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    if (sigprocmask(SIG_BLOCK, &signals, nullptr) != 0) return -1;
    return signalfd(-1, &signals, SFD_CLOEXEC | SFD_NONBLOCK);
}

int run_simulator(const RunOptions& options) {
    set_log_level(options.log_level);
    request_realtime(options.realtime_priority, "ecsim event loop");

    const int stop_fd = open_stop_signals();
    if (stop_fd < 0) return fail("signalfd: " + std::error_code(errno, std::generic_category()).message());

    auto config = eni::load_eni_file(options.eni.string());
    if (!config) return fail(config.error().describe());
    auto segment = sim::Segment::from_eni(**config, options.segment);
    if (!segment) return fail(segment.error().describe());
    const auto& clocks = options.segment.clocks;
    const auto& delays = options.segment.propagation;
    main_log().info("clocks: drift up to {} ppm from seed {}{}; delays: cable {} ns, ESC {} ns alongside / {} ns through its EPU",
                    clocks.drift_ppm, clocks.seed, clocks.seed == 0 ? " (exact clocks)" : "", delays.cable_ns,
                    delays.forwarding_ns, delays.processing_ns);

    // Only EtherCAT frames concern the segment; anything else the kernel
    // puts on the cable (IPv6 neighbour discovery...) stays out.
    link::PcapLinkOptions link_options;
    link_options.bpf_filter = "ether proto 0x88a4";
    auto main_link = link::PcapLink::open(options.main_if, link_options);
    if (!main_link) return fail("MAIN: " + main_link.error().message);
    std::unique_ptr<link::Link> red_link;
    if (options.red_if) {
        auto opened = link::PcapLink::open(*options.red_if, link_options);
        if (!opened) return fail("RED: " + opened.error().message);
        red_link = std::move(opened).value();
    }

    std::vector<std::string> watched{options.main_if};
    if (options.red_if) watched.push_back(*options.red_if);
    auto monitor = link::LinkStateMonitor::open(watched);
    if (!monitor) return fail("link state monitor: " + monitor.error().message);

    std::optional<sim::PcapRecorder> pcap;
    if (options.pcap) {
        auto recorder = sim::PcapRecorder::create(options.pcap->string());
        if (!recorder) return fail(recorder.error().message);
        pcap.emplace(std::move(recorder).value());
    }

    RunnerSetup setup{std::move(segment).value(),
                      std::move(main_link).value(),
                      std::move(red_link),
                      {},
                      std::move(pcap),
                      options.control,
                      stop_fd,
                      {}};
    setup.link_states.push_back(std::move(monitor).value());
    // The interfaces show the carrier of the slave PHY they face (a veth's
    // carrier follows its peer's administrative state).
    auto admin = link::LinkAdmin::open();
    if (admin) {
        std::shared_ptr<link::LinkAdmin> shared = std::move(admin).value();
        const std::array<std::string, 2> names{options.main_if, options.red_if.value_or(std::string())};
        setup.set_carrier = [shared, names](sim::Side side, bool up) -> Expected<bool, std::string> {
            const auto& name = names[static_cast<std::size_t>(side)];
            if (!up) {
                // Down already: someone else's doing, and theirs to undo.
                auto is_up = shared->is_up(name);
                if (!is_up) return unexpected(is_up.error().message);
                if (!*is_up) return false;
            }
            auto set = shared->set_up(name, up);
            if (!set) return unexpected(set.error().message);
            return true;
        };
    } else {
        main_log().warn("interfaces keep their carrier when a slave PHY is gone: {}", admin.error().message);
    }
    auto runner = SegmentRunner::create(std::move(setup));
    if (!runner) return fail(runner.error());
    const int status = (*runner)->run();
    runner.value().reset();  // flushes the pcap file and removes the control socket
    ::close(stop_fd);
    return status;
}

}  // namespace
}  // namespace ecpair::ecsim

int main(int argc, char** argv) {
    using namespace ecpair::ecsim;
    const std::vector<std::string> arguments(argv + 1, argv + argc);
    const auto invocation = parse_command_line(arguments);
    if (!invocation) {
        std::fprintf(stderr, "ecsim: %s\n\n%s", invocation.error().message.c_str(), usage_text().c_str());
        return kExitUsage;
    }
    if (std::holds_alternative<HelpRequest>(*invocation)) {
        std::fputs(usage_text().c_str(), stdout);
        return kExitOk;
    }
    if (const auto* ctl = std::get_if<CtlOptions>(&*invocation)) return run_control_client(*ctl);
    return run_simulator(std::get<RunOptions>(*invocation));
}
