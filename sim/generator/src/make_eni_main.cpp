// ecsim-make-eni: writes a synthetic ENI (see eni_generator.hpp) to a file.

#include <fstream>
#include <iostream>

#include <boost/program_options.hpp>

#include "ecpair/sim/eni_generator.hpp"

int main(int argc, char** argv) {
    namespace po = boost::program_options;
    ecpair::sim::GeneratedEniOptions options;
    std::string output;
    po::options_description desc("ecsim-make-eni: write a synthetic ENI of simple IO slaves");
    desc.add_options()
        ("help,h", "this text")
        ("slaves", po::value(&options.slaves)->default_value(options.slaves), "number of slaves (1..512)")
        ("input-bytes", po::value(&options.input_bytes)->default_value(options.input_bytes), "inputs per slave (0..1024)")
        ("output-bytes", po::value(&options.output_bytes)->default_value(options.output_bytes), "outputs per slave (0..1024)")
        ("cycle-us", po::value(&options.cycle_time_us)->default_value(options.cycle_time_us), "cycle time in µs")
        ("output,o", po::value(&output)->required(), "file to write");
    po::variables_map vm;
    try {
        po::store(po::parse_command_line(argc, argv, desc), vm);
        if (vm.count("help") != 0) {
            std::cout << desc;
            return 0;
        }
        po::notify(vm);
    } catch (const po::error& e) {
        std::cerr << "ecsim-make-eni: " << e.what() << "\n" << desc;
        return 2;
    }
    if (options.slaves < 1 || options.slaves > 512 || options.input_bytes > 1024 || options.output_bytes > 1024) {
        std::cerr << "ecsim-make-eni: --slaves must be 1..512, --input-bytes and --output-bytes 0..1024\n";
        return 2;
    }
    std::ofstream out(output);
    if (!out) {
        std::cerr << "ecsim-make-eni: cannot write " << output << "\n";
        return 2;
    }
    out << ecpair::sim::generate_eni(options);
    return out ? 0 : 2;
}
