#pragma once
// The ENI (EtherCAT Network Information, ETG.2100) as an immutable model.
// load_eni() builds it; everything downstream (ecsim, the master, the
// redundancy fingerprint) reads it and never changes it.
//
// Field names follow the ENI elements. Optional elements are std::optional;
// repeated ones are vectors in file order. Every element that a later error
// message may need to point at keeps its source line.

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ecpair/wire/command.hpp"
#include "ecpair/wire/mac_address.hpp"

namespace ecpair::eni {

// ---------------------------------------------------------------- states

// EtherCAT state machine states with their AL status codes.
enum class SlaveState : std::uint8_t { Init = 1, Preop = 2, Boot = 3, Safeop = 4, Op = 8 };

std::string_view to_string(SlaveState state);

// A set of cyclic-command states (PREOP/SAFEOP/OP) as bits.
class StateSet {
public:
    void add(SlaveState s) { bits_ = static_cast<std::uint16_t>(bits_ | (1u << static_cast<unsigned>(s))); }
    bool contains(SlaveState s) const { return (bits_ & (1u << static_cast<unsigned>(s))) != 0; }
    bool empty() const { return bits_ == 0; }
    friend bool operator==(const StateSet&, const StateSet&) = default;

private:
    std::uint16_t bits_ = 0;
};

// InitCmd transition codes. OP means OP->PREOP; PP is used for "clear DC activation".
enum class Transition : std::uint8_t { IP, PS, SO, SP, OP, OS, PI, SI, OI, IB, BI, II, PP };

inline constexpr std::size_t kTransitionCount = 13;
std::string_view to_string(Transition t);
SlaveState from_state(Transition t);
SlaveState to_state(Transition t);

class TransitionSet {
public:
    void add(Transition t) { bits_ = static_cast<std::uint16_t>(bits_ | (1u << static_cast<unsigned>(t))); }
    bool contains(Transition t) const { return (bits_ & (1u << static_cast<unsigned>(t))) != 0; }
    bool empty() const { return bits_ == 0; }
    friend bool operator==(const TransitionSet&, const TransitionSet&) = default;

private:
    std::uint16_t bits_ = 0;
};

// ---------------------------------------------------------------- InitCmds

enum class Requires : std::uint8_t { None, Cycle, Frame };

// <Validate>: re-read until (read & mask) == (data & mask) or the timeout passes.
struct Validate {
    std::vector<std::uint8_t> data;
    std::vector<std::uint8_t> mask;  // empty: compare every bit
    std::chrono::milliseconds timeout{0};
};

// A register InitCmd (master or slave <InitCmds>) and also a Hot-Connect IdentifyCmd.
struct EcatCmd {
    TransitionSet transitions;  // empty for IdentifyCmds
    bool before_slave = false;
    std::string comment;
    Requires requires_ = Requires::None;
    wire::Command command = wire::Command::Nop;
    // Adp/Ado for physical commands (Adp as written: AutoIncAddr or PhysAddr),
    // or the logical address in `logical_address` for Lxx.
    std::uint16_t adp = 0;
    std::uint16_t ado = 0;
    std::uint32_t logical_address = 0;
    std::vector<std::uint8_t> data;  // <Data>, or <DataLength> zero bytes
    std::optional<std::uint16_t> expected_wkc;  // <Cnt>
    std::uint32_t retries = 0;
    std::optional<std::chrono::milliseconds> timeout;
    std::optional<Validate> validate;
    int source_line = 0;
};

// A CoE InitCmd from <Mailbox><CoE><InitCmds>, kept as data.
struct CoeInitCmd {
    TransitionSet transitions;
    bool fixed = false;
    bool complete_access = false;
    bool disabled = false;  // EAS writes <Disabled>
    std::string comment;
    std::chrono::milliseconds timeout{0};
    std::uint8_t ccs = 1;  // 1 download, 2 upload (Advantech writes 2 with data: see docs)
    std::uint16_t index = 0;
    std::uint8_t subindex = 0;
    std::vector<std::uint8_t> data;
    int source_line = 0;
};

// ---------------------------------------------------------------- slave

struct Identification {
    std::uint16_t ado = 0;                 // 0x0134 explicit device ID, 0x0012 station alias
    std::optional<std::uint16_t> value;    // the expected identification value
    bool enabled = true;                   // EAS writes EnableIdentification="False" to switch the check off
};

struct SlaveInfo {
    std::string name;
    std::uint16_t phys_addr = 0;
    std::uint16_t auto_inc_addr = 0;  // as written: 0, 65535, 65534... (Advantech: 0, 1, 2...)
    // 0-based position in the ring, derived by the loader from AutoIncAddr with
    // one reading per file (docs/ENI.md "Ring positions").
    std::uint16_t ring_position = 0;
    std::string physics;              // one letter per port: Y, K, ...
    std::uint32_t vendor_id = 0;
    std::uint32_t product_code = 0;
    std::uint32_t revision_no = 0;
    std::optional<std::uint32_t> serial_no;
    std::optional<Identification> identification;
};

struct BitRange {
    std::uint32_t bit_start = 0;
    std::uint32_t bit_length = 0;
};

enum class SmType : std::uint8_t { Unused, MailboxOut, MailboxIn, Outputs, Inputs };
std::string_view to_string(SmType type);

struct SyncManager {
    std::uint8_t index = 0;  // Sm0..Sm7
    SmType type = SmType::Unused;
    std::optional<std::uint16_t> min_size, max_size, default_size;
    std::optional<std::uint16_t> start_address;
    std::optional<std::uint8_t> control_byte;
    std::optional<bool> enable;
    std::vector<std::uint16_t> pdos;  // assigned PDO indices
};

struct PdoEntry {
    std::uint16_t index = 0;  // 0 for a padding entry
    std::uint8_t subindex = 0;
    std::uint16_t bit_length = 0;
    std::string name;
    std::string data_type;
};

struct Pdo {
    std::uint16_t index = 0;
    std::string name;
    std::optional<std::uint8_t> sm;
    bool fixed = false;
    bool mandatory = false;
    std::vector<std::uint16_t> excludes;
    std::vector<PdoEntry> entries;
};

struct ProcessData {
    std::optional<BitRange> send;  // outputs (master -> slave)
    std::optional<BitRange> recv;  // inputs (slave -> master)
    std::vector<SyncManager> sync_managers;
    std::vector<Pdo> tx_pdos;  // inputs
    std::vector<Pdo> rx_pdos;  // outputs
};

enum MailboxProtocol : std::uint16_t {
    kAoE = 0x01, kEoE = 0x02, kCoE = 0x04, kFoE = 0x08, kSoE = 0x10, kVoE = 0x20,
};

struct MailboxArea {
    std::uint16_t start = 0;
    std::uint16_t length = 0;
};

// An EoE InitCmd from <Mailbox><EoE><InitCmds>: an EoE "set IP parameter"
// request kept as its raw mailbox payload.
struct EoeInitCmd {
    TransitionSet transitions;
    bool fixed = false;
    bool disabled = false;  // EAS writes <Disabled>
    std::string comment;
    std::chrono::milliseconds timeout{0};
    std::vector<std::uint8_t> data;
    int source_line = 0;
};

// An SoE InitCmd from <Mailbox><SoE><InitCmds> (ETG.2100): an IDN write
// (OpCode 3) or read (OpCode 1) of a drive's elements, kept as data.
struct SoeInitCmd {
    TransitionSet transitions;
    bool fixed = false;
    bool disabled = false;
    std::string comment;
    std::chrono::milliseconds timeout{0};
    std::uint8_t opcode = 3;  // 3 write, 1 read
    std::uint8_t drive_no = 0;
    std::uint16_t idn = 0;
    std::uint8_t elements = 0x40;  // the value
    std::uint8_t attribute = 0;
    std::vector<std::uint8_t> data;
    int source_line = 0;
};

struct Mailbox {
    std::string data_link_layer;  // attribute, as written
    std::optional<MailboxArea> send;  // master -> slave (SM0)
    std::optional<MailboxArea> recv;  // slave -> master (SM1)
    std::optional<std::uint32_t> poll_time_ms;
    std::optional<std::uint32_t> status_bit_addr;
    std::optional<MailboxArea> bootstrap_send;
    std::optional<MailboxArea> bootstrap_recv;
    // MailboxProtocol bits: every <Protocol>, plus the protocols that have their
    // own element (<CoE>, <EoE>, ...; Advantech lists no <Protocol> at all).
    std::uint16_t protocols = 0;
    std::vector<CoeInitCmd> coe_init_cmds;
    std::vector<EoeInitCmd> eoe_init_cmds;
    std::vector<SoeInitCmd> soe_init_cmds;
    std::optional<std::string> aoe_net_id;  // <AoE><NetId>, e.g. "1.1.1.1.3.234"
};

struct PreviousPort {
    bool selected = false;
    char port = 'A';  // upstream slave's port letter, A..D = port 0..3
    std::uint16_t phys_addr = 0;
};

struct DistributedClocks {
    bool potential_reference_clock = false;
    bool reference_clock = false;
    std::optional<std::uint32_t> cycle_time0_ns;
    std::optional<std::uint32_t> cycle_time1_ns;
    std::optional<std::int32_t> shift_time_ns;
};

// Slave/HotConnect: this slave heads a Hot-Connect group of GroupMemberCnt
// slaves (itself included) identified by the IdentifyCmds.
struct HotConnect {
    std::string group_name;
    std::uint32_t group_member_count = 0;
    std::vector<EcatCmd> identify_cmds;
    int source_line = 0;
};

struct Slave {
    SlaveInfo info;
    ProcessData process_data;
    std::optional<Mailbox> mailbox;
    std::vector<EcatCmd> init_cmds;
    std::vector<PreviousPort> previous_ports;
    std::optional<DistributedClocks> dc;
    std::optional<HotConnect> hot_connect;
    int source_line = 0;
};

// A <Slave> with no PhysAddr, no AutoIncAddr and no InitCmds: a terminal
// without an ESC (TwinCAT 2 lists the EL9011 end cap so, with its name,
// identity and PreviousPort). It has no address and no process data and is
// no part of the ring: kept apart from EniConfig::slaves, for the summary.
struct PassiveSlave {
    std::string name;
    std::optional<std::uint32_t> vendor_id;
    std::optional<std::uint32_t> product_code;
    std::optional<std::uint32_t> revision_no;
    std::vector<PreviousPort> previous_ports;
    int source_line = 0;
    std::size_t file_index = 0;  // 0-based among all <Slave> elements of the file
};

// ---------------------------------------------------------------- master

struct MasterInfo {
    std::string name;
    std::optional<wire::MacAddress> destination;
    std::optional<wire::MacAddress> source;
    std::optional<std::uint16_t> ether_type;  // as a number (the file writes "a488" for 0x88A4)
};

struct MailboxStates {
    std::uint32_t start_addr = 0;
    std::uint32_t count = 0;
};

struct EoeSettings {
    std::uint32_t max_ports = 0, max_frames = 0, max_macs = 0;
};

struct Master {
    MasterInfo info;
    std::optional<MailboxStates> mailbox_states;
    std::optional<EoeSettings> eoe;
    std::vector<EcatCmd> init_cmds;
};

// ---------------------------------------------------------------- cyclic

struct CyclicCmd {
    StateSet states;
    std::string comment;
    wire::Command command = wire::Command::Nop;
    std::uint16_t adp = 0;
    std::uint16_t ado = 0;
    std::uint32_t logical_address = 0;  // <Addr> for Lxx
    std::uint16_t data_length = 0;
    std::optional<std::uint16_t> expected_wkc;  // <Cnt>
    std::optional<std::uint32_t> input_offset;  // <InputOffs>, bytes
    std::optional<std::uint32_t> output_offset; // <OutputOffs>, bytes
    int source_line = 0;
};

struct CyclicFrame {
    std::vector<CyclicCmd> cmds;
    int source_line = 0;
};

struct Cyclic {
    std::optional<std::uint32_t> cycle_time_us;
    std::vector<CyclicFrame> frames;
};

// ---------------------------------------------------------------- process image

struct Variable {
    std::string name;
    std::string comment;
    std::string data_type;
    std::uint32_t bit_size = 0;
    std::uint32_t bit_offset = 0;
};

struct ProcessImageSection {
    std::uint32_t byte_size = 0;
    std::vector<Variable> variables;
};

struct ProcessImage {
    std::optional<ProcessImageSection> inputs;
    std::optional<ProcessImageSection> outputs;
};

// ---------------------------------------------------------------- whole file

struct EniConfig {
    std::string source_path;   // as given to the loader ("<memory>" for strings)
    std::string root_element;  // EtherCATConfig or EncryptedEtherCATConfig
    std::optional<std::string> version;
    Master master;
    std::vector<Slave> slaves;  // in file (= ring) order
    std::vector<PassiveSlave> passive_slaves;  // in file order; no part of the ring
    std::vector<Cyclic> cyclic;
    std::optional<ProcessImage> process_image;
    std::uint64_t content_hash = 0;  // FNV-1a 64 over the file bytes

    bool uses_logical_read_write() const;  // any cyclic LRW
};

}  // namespace ecpair::eni
