// Boost.Program_options for ecsim's two modes. The first argument "ctl"
// selects the client mode; everything else is the simulator. Boost's
// exceptions are caught here and turned into UsageErrors that say which
// option was wrong.

#include "command_line.hpp"

// GCC 12 reports a "potential null pointer dereference" inside Boost's
// typed_value<std::string>::notify() once it is inlined at -O2 (a false
// positive in library code): silenced for that header only.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wnull-dereference"
#include <boost/program_options.hpp>
#pragma GCC diagnostic pop
#include <fmt/format.h>

#include <array>
#include <sstream>

namespace ecpair::ecsim {

namespace po = boost::program_options;

namespace {

constexpr std::uint32_t kMaxDriftPpm = 1'000;
constexpr std::uint32_t kMaxDelayNs = 100'000;

constexpr std::array<std::string_view, 7> kLogLevels{"trace", "debug", "info", "warn", "error", "critical", "off"};

bool is_log_level(const std::string& level) {
    for (const auto known : kLogLevels) {
        if (level == known) return true;
    }
    return false;
}

bool is_interface_name(const std::string& name) {
    // Linux: 1..15 characters, no '/', no whitespace, not "." or "..".
    if (name.empty() || name.size() > 15 || name == "." || name == "..") return false;
    for (const char c : name) {
        if (c == '/' || c == ':' || static_cast<unsigned char>(c) <= ' ') return false;
    }
    return true;
}

po::options_description run_description() {
    po::options_description options("ecsim options");
    // clang-format off
    options.add_options()
        ("help,h", "show this help")
        ("eni", po::value<std::string>(), "ENI file whose slaves form the segment (required)")
        ("main-if", po::value<std::string>(), "interface of the MAIN side: the first slave's port A (required)")
        ("red-if", po::value<std::string>(), "interface of the RED side: the ring's return port")
        ("pcap", po::value<std::string>(), "record every frame in and out of the segment to this pcap file")
        ("control", po::value<std::string>(), "control socket path (default /run/ecsim/<main-if>.sock)")
        ("log-level", po::value<std::string>()->default_value("info"),
         "trace, debug, info, warn, error, critical or off")
        ("realtime-priority", po::value<int>()->default_value(0),
         "SCHED_FIFO priority of the event loop, 0 = normal scheduling (real ESCs add no latency; "
         "on a loaded machine this keeps the simulated one small)")
        ("dc-drift-ppm", po::value<std::uint32_t>()->default_value(sim::ClockOptions{}.drift_ppm),
         "each ESC's oscillator is off by up to this much, drawn from the seed (0..1000; ESC crystals are "
         "+-25 ppm)")
        ("dc-seed", po::value<std::uint64_t>()->default_value(sim::ClockOptions{}.seed),
         "seed of the oscillators' drifts and power-on times (0: exact clocks that start together)")
        ("dc-cable-delay-ns", po::value<std::uint32_t>()->default_value(sim::PropagationOptions{}.cable_ns),
         "a cable from port to port, PHYs included")
        ("dc-forwarding-delay-ns", po::value<std::uint32_t>()->default_value(sim::PropagationOptions{}.forwarding_ns),
         "through an ESC alongside its processing unit")
        ("dc-processing-delay-ns", po::value<std::uint32_t>()->default_value(sim::PropagationOptions{}.processing_ns),
         "through an ESC's processing unit");
    // clang-format on
    return options;
}

po::options_description ctl_description() {
    po::options_description options("ecsim ctl options");
    // clang-format off
    options.add_options()
        ("help,h", "show this help")
        ("control", po::value<std::string>(), "control socket of the ecsim to talk to")
        ("main-if", po::value<std::string>(), "or: its MAIN interface (socket /run/ecsim/<main-if>.sock)")
        ("json", "for requests that offer it (dc): print the JSON alone");
    // clang-format on
    return options;
}

po::variables_map parse(const std::vector<std::string>& arguments, const po::options_description& options,
                        const po::positional_options_description* positional) {
    po::variables_map values;
    auto parser = po::command_line_parser(arguments).options(options);
    if (positional != nullptr) parser.positional(*positional);
    po::store(parser.run(), values);
    po::notify(values);
    return values;
}

Expected<Invocation, UsageError> parse_ctl(const std::vector<std::string>& arguments) {
    po::options_description words;
    words.add_options()("command", po::value<std::vector<std::string>>(), "the request words");
    po::options_description all;
    all.add(ctl_description()).add(words);
    po::positional_options_description positional;
    positional.add("command", -1);
    const auto values = parse(arguments, all, &positional);
    if (values.count("help") != 0) return Invocation{HelpRequest{}};

    CtlOptions options;
    if (values.count("control") != 0) {
        options.control = values["control"].as<std::string>();
    } else if (values.count("main-if") != 0) {
        options.control = default_control_path(values["main-if"].as<std::string>());
    } else {
        return unexpected(UsageError{"ctl needs --control PATH (or --main-if IF)"});
    }
    if (values.count("command") == 0) return unexpected(UsageError{"ctl needs a COMMAND (try: ecsim ctl ... help)"});
    for (const auto& word : values["command"].as<std::vector<std::string>>()) {
        if (!options.request.empty()) options.request += ' ';
        options.request += word;
    }
    if (options.request.find('\n') != std::string::npos) {
        return unexpected(UsageError{"the COMMAND must not contain a newline"});
    }
    if (values.count("json") != 0) {
        options.json = true;
        options.request += " --json";
    }
    return Invocation{std::move(options)};
}

Expected<Invocation, UsageError> parse_run(const std::vector<std::string>& arguments) {
    const auto values = parse(arguments, run_description(), nullptr);
    if (values.count("help") != 0) return Invocation{HelpRequest{}};

    RunOptions options;
    if (values.count("eni") == 0) return unexpected(UsageError{"--eni FILE is required"});
    if (values.count("main-if") == 0) return unexpected(UsageError{"--main-if IF is required"});
    options.eni = values["eni"].as<std::string>();
    options.main_if = values["main-if"].as<std::string>();
    if (!is_interface_name(options.main_if)) {
        return unexpected(UsageError{fmt::format("--main-if: '{}' is not an interface name", options.main_if)});
    }
    if (values.count("red-if") != 0) {
        options.red_if = values["red-if"].as<std::string>();
        if (!is_interface_name(*options.red_if)) {
            return unexpected(UsageError{fmt::format("--red-if: '{}' is not an interface name", *options.red_if)});
        }
        if (*options.red_if == options.main_if) {
            return unexpected(UsageError{"--red-if must differ from --main-if"});
        }
    }
    if (values.count("pcap") != 0) options.pcap = values["pcap"].as<std::string>();
    options.control = values.count("control") != 0 ? std::filesystem::path(values["control"].as<std::string>())
                                                   : default_control_path(options.main_if);
    options.log_level = values["log-level"].as<std::string>();
    if (!is_log_level(options.log_level)) {
        return unexpected(UsageError{fmt::format(
            "--log-level: '{}' is not one of trace, debug, info, warn, error, critical, off", options.log_level)});
    }
    options.realtime_priority = values["realtime-priority"].as<int>();
    if (options.realtime_priority < 0 || options.realtime_priority > 99) {
        return unexpected(
            UsageError{fmt::format("--realtime-priority: must be 0..99 (got {})", options.realtime_priority)});
    }
    sim::SegmentOptions& segment = options.segment;
    segment.clocks.drift_ppm = values["dc-drift-ppm"].as<std::uint32_t>();
    segment.clocks.seed = values["dc-seed"].as<std::uint64_t>();
    segment.propagation.cable_ns = values["dc-cable-delay-ns"].as<std::uint32_t>();
    segment.propagation.forwarding_ns = values["dc-forwarding-delay-ns"].as<std::uint32_t>();
    segment.propagation.processing_ns = values["dc-processing-delay-ns"].as<std::uint32_t>();
    if (segment.clocks.drift_ppm > kMaxDriftPpm) {
        return unexpected(UsageError{fmt::format(
            "--dc-drift-ppm: must be 0..{} (got {}; the ESC's time control loop corrects at most ~760 ppm)",
            kMaxDriftPpm, segment.clocks.drift_ppm)});
    }
    for (const auto& [name, value] : {std::pair{"--dc-cable-delay-ns", segment.propagation.cable_ns},
                                      std::pair{"--dc-forwarding-delay-ns", segment.propagation.forwarding_ns},
                                      std::pair{"--dc-processing-delay-ns", segment.propagation.processing_ns}}) {
        if (value > kMaxDelayNs) {
            return unexpected(UsageError{fmt::format("{}: must be 0..{} ns (got {})", name, kMaxDelayNs, value)});
        }
    }
    return Invocation{std::move(options)};
}

}  // namespace

std::filesystem::path default_control_path(const std::string& main_if) {
    return std::filesystem::path("/run/ecsim") / (main_if + ".sock");
}

Expected<Invocation, UsageError> parse_command_line(const std::vector<std::string>& arguments) {
    try {
        if (!arguments.empty() && arguments.front() == "ctl") {
            return parse_ctl(std::vector<std::string>(arguments.begin() + 1, arguments.end()));
        }
        return parse_run(arguments);
    } catch (const po::error& error) {
        return unexpected(UsageError{error.what()});
    }
}

std::string usage_text() {
    std::ostringstream text;
    text << "usage: ecsim --eni FILE --main-if IF [--red-if IF] [--pcap FILE] [--control PATH] [--log-level L]\n"
            "             [--realtime-priority N] [--dc-drift-ppm MAX] [--dc-seed N] [--dc-cable-delay-ns N]\n"
            "             [--dc-forwarding-delay-ns N] [--dc-processing-delay-ns N]\n"
         << "       ecsim ctl (--control PATH | --main-if IF) [--json] COMMAND [ARG...]\n\n"
         << run_description() << '\n'
         << ctl_description() << '\n'
         << "ctl exit status: 0 ok, 1 error response, 2 usage, 3 no ecsim on the socket\n";
    return text.str();
}

}  // namespace ecpair::ecsim
