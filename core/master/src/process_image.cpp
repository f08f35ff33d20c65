#include "ecpair/master/process_image.hpp"

#include <algorithm>
#include <cassert>

namespace ecpair::master {
std::size_t ProcessImage::bytes_needed(const std::optional<eni::ProcessImageSection>& section) {
    if (!section) return 0;
    std::size_t size = section->byte_size;
    for (const auto& v : section->variables) {
        size = std::max<std::size_t>(size, (static_cast<std::size_t>(v.bit_offset) + v.bit_size + 7) / 8);
    }
    return size;
}

std::uint64_t read_bits(ConstBytes bytes, std::uint32_t bit_offset, std::uint32_t bit_size) {
    assert(bit_size <= 64);
    std::uint64_t value = 0;
    if (bit_offset % 8 == 0 && bit_size % 8 == 0) {
        for (std::uint32_t i = 0; i < bit_size / 8; ++i) {
            value |= static_cast<std::uint64_t>(bytes[bit_offset / 8 + i]) << (8 * i);
        }
        return value;
    }
    for (std::uint32_t i = 0; i < bit_size; ++i) {
        const std::uint32_t bit = bit_offset + i;
        if ((static_cast<unsigned>(bytes[bit / 8]) >> (bit % 8)) & 1u) value |= std::uint64_t{1} << i;
    }
    return value;
}

void write_bits(Bytes bytes, std::uint32_t bit_offset, std::uint32_t bit_size, std::uint64_t value) {
    assert(bit_size <= 64);
    if (bit_offset % 8 == 0 && bit_size % 8 == 0) {
        for (std::uint32_t i = 0; i < bit_size / 8; ++i) {
            bytes[bit_offset / 8 + i] = static_cast<std::uint8_t>(value >> (8 * i));
        }
        return;
    }
    for (std::uint32_t i = 0; i < bit_size; ++i) {
        const std::uint32_t bit = bit_offset + i;
        const auto mask = static_cast<std::uint8_t>(1u << (bit % 8));
        if ((value >> i) & 1u) {
            bytes[bit / 8] |= mask;
        } else {
            bytes[bit / 8] = static_cast<std::uint8_t>(bytes[bit / 8] & ~mask);
        }
    }
}

ProcessImage::ProcessImage(std::size_t input_size, std::size_t output_size,
                           const std::optional<eni::ProcessImage>& layout)
    : layout_(layout) {
    const auto* in = layout_ ? &layout_->inputs : nullptr;
    const auto* out = layout_ ? &layout_->outputs : nullptr;
    inputs_.assign(std::max(input_size, in ? bytes_needed(*in) : 0), 0);
    outputs_.assign(std::max(output_size, out ? bytes_needed(*out) : 0), 0);

    auto index = [this](const std::optional<eni::ProcessImageSection>& section, ImageSection which,
                        std::vector<VariableRef>& refs) {
        if (!section) return;
        for (const auto& v : section->variables) {
            if (v.bit_size == 0 || v.bit_size > 64) continue;  // blobs are reached through the raw image
            VariableRef ref{which, v.bit_offset, v.bit_size, &v};
            refs.push_back(ref);
            by_name_.emplace(v.name, ref);  // the first of duplicate names wins
        }
    };
    if (layout_) {
        index(layout_->inputs, ImageSection::Inputs, input_refs_);
        index(layout_->outputs, ImageSection::Outputs, output_refs_);
    }
}

std::optional<VariableRef> ProcessImage::find(std::string_view name) const {
    const auto it = by_name_.find(std::string(name));
    if (it == by_name_.end()) return std::nullopt;
    return it->second;
}

std::uint64_t ProcessImage::read_bits(const VariableRef& ref) const {
    return master::read_bits(section(ref.section), ref.bit_offset, ref.bit_size);
}

void ProcessImage::write_bits(const VariableRef& ref, std::uint64_t value) {
    master::write_bits(section(ref.section), ref.bit_offset, ref.bit_size, value);
}

void ProcessImage::assign(ConstBytes inputs, ConstBytes outputs) {
    assert(inputs.size() == inputs_.size() && outputs.size() == outputs_.size());
    std::copy(inputs.begin(), inputs.end(), inputs_.begin());
    std::copy(outputs.begin(), outputs.end(), outputs_.begin());
}

}  // namespace ecpair::master
