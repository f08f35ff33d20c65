// ecsim-make-eni: writes a synthetic ENI (see eni_generator.hpp) to a file.

#include <fstream>
#include <iostream>

#include <boost/program_options.hpp>

#include "ecpair/sim/eni_generator.hpp"

int main(int argc, char** argv) {
    namespace po = boost::program_options;
    ecpair::sim::GeneratedEniOptions options;
    std::string output;
    std::string identification = "alias";
    po::options_description desc("ecsim-make-eni: write a synthetic ENI of simple IO slaves (and Hot-Connect groups)");
    desc.add_options()
        ("help,h", "this text")
        ("slaves", po::value(&options.slaves)->default_value(options.slaves), "number of slaves (1..512)")
        ("input-bytes", po::value(&options.input_bytes)->default_value(options.input_bytes), "inputs per slave (0..1024)")
        ("output-bytes", po::value(&options.output_bytes)->default_value(options.output_bytes), "outputs per slave (0..1024)")
        ("cycle-us", po::value(&options.cycle_time_us)->default_value(options.cycle_time_us), "cycle time in µs")
        ("groups", po::value(&options.groups)->default_value(options.groups),
         "Hot-Connect groups, one at port D of each of the first N slaves of the line")
        ("group-slaves", po::value(&options.group_slaves)->default_value(options.group_slaves), "slaves per group (1..64)")
        ("identification", po::value(&identification)->default_value(identification),
         "group identification: none, alias, explicit or input-word (value 100 + group number)")
        ("floating", po::bool_switch(&options.floating), "the groups float (no PreviousPort; ecsim starts them unplugged)")
        ("coe-groups", po::bool_switch(&options.coe_groups), "group slaves are CoE drives (mailbox, SDO InitCmds)")
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
    using Id = ecpair::sim::GeneratedEniOptions::Identification;
    if (identification == "none") {
        options.identification = Id::None;
    } else if (identification == "alias") {
        options.identification = Id::StationAlias;
    } else if (identification == "explicit") {
        options.identification = Id::ExplicitDeviceId;
    } else if (identification == "input-word") {
        options.identification = Id::InputWord;
    } else {
        std::cerr << "ecsim-make-eni: --identification must be none, alias, explicit or input-word, got '"
                  << identification << "'\n";
        return 2;
    }
    if (const auto problem = ecpair::sim::check_options(options)) {
        std::cerr << "ecsim-make-eni: " << *problem << "\n";
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
