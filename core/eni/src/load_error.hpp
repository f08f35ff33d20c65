#pragma once
// The loader's internal failure signal. Readers deep inside the element tree
// throw LoadError at the element that is wrong; load_eni_string() catches it
// once and turns it into the public EniError (adding the file name). It never
// escapes the library.

#include <stdexcept>
#include <string>

namespace ecpair::eni::detail {

class LoadError : public std::runtime_error {
public:
    LoadError(int line, std::string element_path, const std::string& message)
        : std::runtime_error(message), line_(line), element_path_(std::move(element_path)) {}

    int line() const { return line_; }
    const std::string& element_path() const { return element_path_; }

private:
    int line_;
    std::string element_path_;
};

}  // namespace ecpair::eni::detail
