#include "esc_test_support.hpp"

#include <stdexcept>

namespace ecpair::sim::test {
namespace {

eni::PdoEntry entry(std::uint16_t index, std::uint8_t subindex, std::uint16_t bits, const char* type) {
    eni::PdoEntry e;
    e.index = index;
    e.subindex = subindex;
    e.bit_length = bits;
    e.data_type = type;
    return e;
}

eni::SyncManager sm(std::uint8_t index, eni::SmType type, std::uint16_t start, std::uint8_t control,
                    std::vector<std::uint16_t> pdos) {
    eni::SyncManager s;
    s.index = index;
    s.type = type;
    s.start_address = start;
    s.control_byte = control;
    s.enable = true;
    s.pdos = std::move(pdos);
    return s;
}

}  // namespace

EscDescription drive_description(const std::string& name) {
    EscDescription d;
    d.name = name;
    d.vendor_id = 0x0000009A;
    d.product_code = 0x00030924;
    d.revision_no = 0x00010420;
    d.serial_no = 0x00C0FFEE;
    d.physics = "YY";
    eni::Mailbox mailbox;
    mailbox.send = eni::MailboxArea{0x1000, 128};
    mailbox.recv = eni::MailboxArea{0x1080, 128};
    mailbox.bootstrap_send = eni::MailboxArea{0x1000, 128};
    mailbox.bootstrap_recv = eni::MailboxArea{0x1080, 128};
    mailbox.protocols = eni::kCoE | eni::kFoE;
    d.mailbox = mailbox;

    eni::Pdo rx;
    rx.index = 0x1600;
    rx.sm = 2;
    rx.entries = {entry(0x6040, 0, 16, "UINT"), entry(0x607A, 0, 32, "DINT")};
    eni::Pdo tx;
    tx.index = 0x1A00;
    tx.sm = 3;
    tx.entries = {entry(0x6041, 0, 16, "UINT"), entry(0x6064, 0, 32, "DINT"), entry(0x6061, 0, 8, "SINT"),
                  entry(0, 0, 8, "")};
    d.process_data.rx_pdos = {rx};
    d.process_data.tx_pdos = {tx};
    d.process_data.sync_managers = {sm(2, eni::SmType::Outputs, 0x1100, 0x64, {0x1600}),
                                    sm(3, eni::SmType::Inputs, 0x1180, 0x20, {0x1A00})};
    d.process_data.send = eni::BitRange{0, 48};
    d.process_data.recv = eni::BitRange{0, 64};
    return d;
}

EscDescription io_description(const std::string& name) {
    EscDescription d;
    d.name = name;
    d.vendor_id = 2;
    d.product_code = 0x07D83052;
    d.revision_no = 0x00100000;
    d.physics = "KK";
    eni::Pdo rx;
    rx.index = 0x1600;
    rx.sm = 2;
    rx.entries = {entry(0x7000, 1, 8, "USINT")};
    d.process_data.rx_pdos = {rx};
    d.process_data.sync_managers = {sm(2, eni::SmType::Outputs, 0x1000, 0x44, {0x1600})};
    return d;
}

EscDescription coupler_description() {
    EscDescription d;
    d.name = "coupler";
    d.vendor_id = 2;
    d.product_code = 0x044C2C52;
    d.physics = "YYY";
    return d;
}

EscDescription digital_output_description(const std::string& name) {
    EscDescription d;
    d.name = name;
    d.vendor_id = 2;
    d.product_code = 0x07D83052;
    d.revision_no = 0x00100000;
    d.physics = "KK";
    std::vector<std::uint16_t> pdos;
    for (std::uint16_t channel = 0; channel < 8; ++channel) {
        eni::Pdo rx;
        rx.index = static_cast<std::uint16_t>(0x1600 + channel);
        rx.sm = 0;
        rx.fixed = true;
        rx.entries = {entry(static_cast<std::uint16_t>(0x7000 + 0x10 * channel), 1, 1, "BOOL")};
        d.process_data.rx_pdos.push_back(rx);
        pdos.push_back(rx.index);
    }
    d.process_data.sync_managers = {sm(0, eni::SmType::Outputs, 0x0F00, 0x44, pdos)};
    return d;
}

std::vector<std::uint8_t> le16(std::uint16_t value) {
    return {static_cast<std::uint8_t>(value), static_cast<std::uint8_t>(value >> 8)};
}

std::vector<std::uint8_t> le32(std::uint32_t value) {
    return {static_cast<std::uint8_t>(value), static_cast<std::uint8_t>(value >> 8), static_cast<std::uint8_t>(value >> 16),
            static_cast<std::uint8_t>(value >> 24)};
}

std::vector<std::uint8_t> bytes(std::initializer_list<int> values) {
    std::vector<std::uint8_t> out;
    for (const int v : values) out.push_back(static_cast<std::uint8_t>(v));
    return out;
}

Datagram physical(wire::Command command, std::uint16_t adp, std::uint16_t ado, std::vector<std::uint8_t> data) {
    Datagram d;
    d.command = command;
    d.address = wire::DatagramHeader::physical(adp, ado);
    d.data = std::move(data);
    return d;
}

Datagram physical_read(wire::Command command, std::uint16_t adp, std::uint16_t ado, std::size_t length) {
    return physical(command, adp, ado, std::vector<std::uint8_t>(length, 0));
}

Datagram logical(wire::Command command, std::uint32_t address, std::vector<std::uint8_t> data) {
    Datagram d;
    d.command = command;
    d.address = address;
    d.data = std::move(data);
    return d;
}

Frame::Frame(const std::vector<Datagram>& datagrams, wire::MacAddress source) : buffer_(wire::kMaxFrameSize) {
    wire::EthernetHeader ethernet;
    ethernet.destination = wire::MacAddress::broadcast();
    ethernet.source = source;
    wire::FrameBuilder builder(buffer_, ethernet);
    for (const auto& d : datagrams) {
        wire::DatagramHeader header;
        header.command = d.command;
        header.address = d.address;
        header.circulating = d.circulating;
        header.irq = d.irq;
        auto view = builder.append(header, d.data);
        if (!view) throw std::runtime_error("datagram does not fit");
        view->set_wkc(d.wkc);
    }
    buffer_.resize(builder.finish().size());
}

wire::FrameView Frame::view() {
    auto parsed = wire::FrameView::parse(buffer_);
    if (!parsed) throw std::runtime_error(parsed.error().describe());
    return parsed.value();
}

std::vector<Datagram> Frame::datagrams() {
    std::vector<Datagram> out;
    for (const auto d : view()) {
        Datagram copy;
        copy.command = d.command();
        copy.address = d.address();
        copy.data.assign(d.data().begin(), d.data().end());
        copy.circulating = d.circulating();
        copy.irq = d.irq();
        copy.wkc = d.wkc();
        out.push_back(copy);
    }
    return out;
}

wire::MacAddress Frame::source() { return view().ethernet().source; }

Line::Line(std::vector<EscDescription> slaves) {
    escs_.reserve(slaves.size());
    for (auto& d : slaves) escs_.emplace_back(std::move(d));
    for (std::size_t i = 0; i < escs_.size(); ++i) {
        escs_[i].set_physical_link(0, true);
        if (i + 1 < escs_.size()) escs_[i].set_physical_link(1, true);
    }
}

bool Line::run(Frame& frame) {
    auto view = frame.view();
    const std::uint64_t seq = seq_++;
    for (auto& esc : escs_) {
        time_ns_ += 100;
        esc.frame_arrived_at_port(0, time_ns_, seq);
        if (esc.process(view, FrameContext{time_ns_, seq}) == EpuVerdict::Destroy) return false;
    }
    return true;
}

Datagram Line::transact(const Datagram& datagram) {
    Frame frame({datagram});
    run(frame);
    return frame.datagram(0);
}

std::uint16_t Line::fpwr(std::uint16_t station, std::uint16_t ado, const std::vector<std::uint8_t>& data) {
    return transact(physical(wire::Command::Fpwr, station, ado, data)).wkc;
}

std::vector<std::uint8_t> Line::fprd(std::uint16_t station, std::uint16_t ado, std::size_t length) {
    return transact(physical_read(wire::Command::Fprd, station, ado, length)).data;
}

void Line::assign_station_addresses() {
    for (std::size_t i = 0; i < escs_.size(); ++i) {
        const auto adp = static_cast<std::uint16_t>(0x10000 - i);
        transact(physical(wire::Command::Apwr, adp, 0x0010, le16(static_cast<std::uint16_t>(kFirstStation + i))));
    }
}

std::uint8_t bring_drive_to(Line& line, std::uint16_t station, std::uint8_t target) {
    // SM0/SM1 as the SII says (SOEM writes both in one datagram).
    line.fpwr(station, 0x0800,
              bytes({0x00, 0x10, 0x80, 0x00, 0x26, 0x00, 0x01, 0x00, 0x80, 0x10, 0x80, 0x00, 0x22, 0x00, 0x01, 0x00}));
    line.fpwr(station, 0x0120, le16(0x0012));
    if (target == 0x02) return line.fprd(station, 0x0130, 1)[0];
    line.fpwr(station, 0x0810, bytes({0x00, 0x11, 0x06, 0x00, 0x64, 0x00, 0x01, 0x00}));
    line.fpwr(station, 0x0818, bytes({0x80, 0x11, 0x08, 0x00, 0x20, 0x00, 0x01, 0x00}));
    line.fpwr(station, 0x0120, le16(0x0004));
    if (target == 0x04) return line.fprd(station, 0x0130, 1)[0];
    line.fpwr(station, 0x0120, le16(0x0008));
    return line.fprd(station, 0x0130, 1)[0];
}

}  // namespace ecpair::sim::test
