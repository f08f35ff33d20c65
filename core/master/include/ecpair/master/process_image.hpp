#pragma once
// The process image: the input bytes the slaves deliver and the output bytes
// the application sets, laid out as the ENI says (variable BitOffs and the
// cyclic commands' InputOffs/OutputOffs index the same arrays). Variables are
// found by their ENI name and read/written with bit granularity.
//
// The image belongs to the cycle thread; other threads see copies.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "ecpair/common/bytes.hpp"
#include "ecpair/eni/model.hpp"

namespace ecpair::master {

enum class ImageSection : std::uint8_t { Inputs, Outputs };

struct VariableRef {
    ImageSection section = ImageSection::Inputs;
    std::uint32_t bit_offset = 0;
    std::uint32_t bit_size = 0;
    const eni::Variable* variable = nullptr;  // name, data type, comment
};

class ProcessImage {
public:
    // Larger images are refused (a hostile ENI could otherwise ask for gigabytes).
    static constexpr std::size_t kMaxBytes = 16u << 20;
    // The bytes a section of the layout needs: ByteSize, and every variable inside.
    static std::size_t bytes_needed(const std::optional<eni::ProcessImageSection>& section);

    // Sizes are at least the ENI's ByteSize and cover every variable.
    ProcessImage(std::size_t input_size, std::size_t output_size, const std::optional<eni::ProcessImage>& layout);
    // Variable refs point into the image's own copy of the layout: moving keeps
    // them valid, copying would not.
    ProcessImage(ProcessImage&&) = default;
    ProcessImage& operator=(ProcessImage&&) = default;
    ProcessImage(const ProcessImage&) = delete;
    ProcessImage& operator=(const ProcessImage&) = delete;

    Bytes inputs() { return inputs_; }
    ConstBytes inputs() const { return inputs_; }
    Bytes outputs() { return outputs_; }
    ConstBytes outputs() const { return outputs_; }
    Bytes section(ImageSection s) { return s == ImageSection::Inputs ? Bytes(inputs_) : Bytes(outputs_); }
    ConstBytes section(ImageSection s) const {
        return s == ImageSection::Inputs ? ConstBytes(inputs_) : ConstBytes(outputs_);
    }

    // By the ENI's variable name; nullopt when there is no such variable.
    std::optional<VariableRef> find(std::string_view name) const;
    const std::vector<VariableRef>& variables(ImageSection s) const {
        return s == ImageSection::Inputs ? input_refs_ : output_refs_;
    }

    // Up to 64 bits, little-endian bit order as on the wire; bit_size 1 for BOOL.
    std::uint64_t read_bits(const VariableRef& ref) const;
    void write_bits(const VariableRef& ref, std::uint64_t value);

    // Copies the other image's bytes into this one (the sizes must match).
    void assign(ConstBytes inputs, ConstBytes outputs);

private:
    std::vector<std::uint8_t> inputs_;
    std::vector<std::uint8_t> outputs_;
    std::optional<eni::ProcessImage> layout_;  // owns the Variables the refs point to
    std::vector<VariableRef> input_refs_;
    std::vector<VariableRef> output_refs_;
    std::unordered_map<std::string, VariableRef> by_name_;
};

// Bit-granular copy helpers shared by the image and the cyclic exchange.
std::uint64_t read_bits(ConstBytes bytes, std::uint32_t bit_offset, std::uint32_t bit_size);
void write_bits(Bytes bytes, std::uint32_t bit_offset, std::uint32_t bit_size, std::uint64_t value);

}  // namespace ecpair::master
