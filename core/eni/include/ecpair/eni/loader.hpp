#pragma once
// Loads an ENI file into the immutable model. Errors say where: file, line
// and element path (for example
// "eni.xml:123: /EtherCATConfig/Config/Slave[2]/Info/PhysAddr: '70000' is out of range 0..65535").

#include <memory>
#include <string>
#include <string_view>

#include "ecpair/common/expected.hpp"
#include "ecpair/eni/model.hpp"

namespace ecpair::eni {

struct EniError {
    std::string file;
    int line = 0;              // 0 when the problem has no line (missing file)
    std::string element_path;  // empty when the problem is not in an element
    std::string message;

    std::string describe() const;
};

using EniResult = Expected<std::shared_ptr<const EniConfig>, EniError>;

EniResult load_eni_file(const std::string& path);
// For tests and fuzzing: `name` stands in for the file name in errors.
EniResult load_eni_string(std::string_view xml, const std::string& name = "<memory>");

}  // namespace ecpair::eni
