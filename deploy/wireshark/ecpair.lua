-- Wireshark/tshark dissector for what the two masters of an ecpair pair say
-- to each other on the EtherCAT wire (docs/WIRE_FORMAT.md):
--   * Cyclic Master Red Frame datagrams (NOP, ADP 0, ADO 0x4155, magic "CM"):
--     segment header, the HEADER section (cycle counter, flags, pair
--     parameters, fingerprint; format 2: epoch, hand-off cycle, slaves
--     reached, sender's MAC, send offset) and the STANDBY_STATUS section;
--   * TAP bridge datagrams (NOP, ADP 0, ADO 0x4254, magic "TB"): the bridge
--     header with its CRC checked, and every bridged Ethernet frame handed
--     to Wireshark's Ethernet dissector (so ARP, IP, ICMP, TCP show).
--
-- Usage:  tshark -X lua_script:deploy/wireshark/ecpair.lua -r capture.pcap
--         tshark -X lua_script:deploy/wireshark/ecpair.lua -r c.pcap -Y ecpair.tb -T fields -e ecpair.tb.kind
-- or copy it into ~/.local/lib/wireshark/plugins/.
--
-- It runs after the other dissectors and walks the EtherCAT datagrams itself
-- (Ethernet header, optional VLAN tag, 2-byte EtherCAT header, datagrams
-- chained by their M bit), so it does not depend on how the built-in
-- EtherCAT dissector names its fields.

local ecpair = Proto("ecpair", "ecpair master redundancy")

local CMF_ADO = 0x4155
local BRIDGE_ADO = 0x4254

local section_names = { [1] = "HEADER", [2] = "SLAVE_STATE_IMAGE", [3] = "SHADOW_INPUTS",
                        [4] = "MASTER_PD_OUT", [5] = "MASTER_PD_IN", [6] = "STANDBY_STATUS" }
local state_names = { [1] = "INIT", [2] = "PREOP", [3] = "BOOT", [4] = "SAFEOP", [8] = "OP" }
local bridge_kinds = { [1] = "DATA", [2] = "POLL", [3] = "ANSWER" }

local f = ecpair.fields
-- CMF segment header (16 bytes)
f.cmf = ProtoField.bytes("ecpair.cmf", "Cyclic Master Red Frame datagram")
f.cmf_version = ProtoField.uint8("ecpair.cmf.version", "Format version")
f.cmf_kind = ProtoField.uint8("ecpair.cmf.kind", "Section", base.DEC, section_names)
f.cmf_part = ProtoField.uint16("ecpair.cmf.part", "Part")
f.cmf_part_count = ProtoField.uint16("ecpair.cmf.part_count", "Part count")
f.cmf_offset = ProtoField.uint32("ecpair.cmf.offset", "Offset in section")
f.cmf_cycle_low = ProtoField.uint32("ecpair.cmf.cycle_low", "Cycle (low 32 bits)")
-- CMF HEADER section (68 bytes in format version 1, 92 in version 2)
f.cmf_header_version = ProtoField.uint8("ecpair.cmf.header.version", "Header format version")
f.cmf_master_state = ProtoField.uint8("ecpair.cmf.master_state", "Master state", base.DEC, state_names)
f.cmf_flags = ProtoField.uint16("ecpair.cmf.flags", "Redundancy flags", base.HEX)
f.cmf_ring_broken = ProtoField.bool("ecpair.cmf.flags.ring_broken", "Ring broken", 16, nil, 0x0001)
f.cmf_handoff = ProtoField.bool("ecpair.cmf.flags.handoff_request", "Hand-off request", 16, nil, 0x0002)
f.cmf_cycle = ProtoField.uint64("ecpair.cmf.cycle", "Cycle counter")
f.cmf_slave_count = ProtoField.uint16("ecpair.cmf.slave_count", "Slave count")
f.cmf_header_parts = ProtoField.uint16("ecpair.cmf.header.part_count", "Part count")
f.cmf_ssi_size = ProtoField.uint32("ecpair.cmf.slave_state_image_size", "SLAVE_STATE_IMAGE size")
f.cmf_inputs_size = ProtoField.uint32("ecpair.cmf.shadow_inputs_size", "SHADOW_INPUTS size")
f.cmf_pd_out_size = ProtoField.uint32("ecpair.cmf.master_pd_out_size", "MASTER_PD_OUT size")
f.cmf_pd_in_size = ProtoField.uint32("ecpair.cmf.master_pd_in_size", "MASTER_PD_IN size")
f.cmf_eni_hash = ProtoField.uint64("ecpair.cmf.eni_hash", "ENI content hash", base.HEX)
f.cmf_cycle_time = ProtoField.uint64("ecpair.cmf.cycle_time_ns", "Cycle time (ns)")
f.cmf_max_acyc = ProtoField.uint16("ecpair.cmf.max_acyc_frames", "Max acyclic frames per cycle")
f.cmf_param_flags = ProtoField.uint8("ecpair.cmf.parameter_flags", "Parameter flags", base.HEX)
f.cmf_fingerprint = ProtoField.uint64("ecpair.cmf.fingerprint", "Fingerprint", base.HEX)
f.cmf_epoch = ProtoField.uint32("ecpair.cmf.epoch", "Epoch")
f.cmf_handoff_cycle = ProtoField.uint64("ecpair.cmf.handoff_cycle", "Hand-off cycle")
f.cmf_slaves_reached = ProtoField.uint16("ecpair.cmf.slaves_reached", "Slaves reached")
f.cmf_sender_mac = ProtoField.ether("ecpair.cmf.sender_main_mac", "Sender's MAIN MAC")
f.cmf_send_offset = ProtoField.uint32("ecpair.cmf.send_offset_ns", "Send offset in the sender's cycle (ns)")
-- CMF STANDBY_STATUS section (16 bytes, version 2: the INACTIVE's answer)
f.ss_flags = ProtoField.uint8("ecpair.cmf.standby.flags", "Standby flags", base.HEX)
f.ss_hot = ProtoField.bool("ecpair.cmf.standby.hot", "Hot standby", 8, nil, 0x01)
f.ss_forced = ProtoField.bool("ecpair.cmf.standby.forced", "Forced to standby", 8, nil, 0x02)
f.ss_differs = ProtoField.bool("ecpair.cmf.standby.differs", "Partner differs", 8, nil, 0x04)
f.ss_switchover = ProtoField.bool("ecpair.cmf.standby.switchover", "Switchover requested", 8, nil, 0x08)
f.ss_ack = ProtoField.bool("ecpair.cmf.standby.handoff_ack", "Hand-off acknowledged", 8, nil, 0x10)
f.ss_main_up = ProtoField.bool("ecpair.cmf.standby.main_up", "MAIN link up", 8, nil, 0x20)
f.ss_red_up = ProtoField.bool("ecpair.cmf.standby.red_up", "RED link up", 8, nil, 0x40)
f.ss_mac = ProtoField.ether("ecpair.cmf.standby.main_mac", "INACTIVE's MAIN MAC")
f.ss_ack_cycle = ProtoField.uint32("ecpair.cmf.standby.handoff_cycle_low", "Acknowledged hand-off cycle (low 32 bits)")
f.ss_epoch = ProtoField.uint32("ecpair.cmf.standby.epoch", "Newest epoch known")
-- TAP bridge datagram (24-byte header, then frames behind 2-byte lengths)
f.tb = ProtoField.bytes("ecpair.tb", "TAP bridge datagram")
f.tb_version = ProtoField.uint8("ecpair.tb.version", "Format version")
f.tb_kind = ProtoField.uint8("ecpair.tb.kind", "Kind", base.DEC, bridge_kinds)
f.tb_length = ProtoField.uint16("ecpair.tb.length", "Payload length")
f.tb_frames = ProtoField.uint8("ecpair.tb.frames", "Frames")
f.tb_session = ProtoField.uint32("ecpair.tb.session", "Writer's session", base.HEX)
f.tb_sequence = ProtoField.uint32("ecpair.tb.sequence", "Sequence")
f.tb_backlog = ProtoField.uint16("ecpair.tb.backlog", "Writer's backlog (bytes)")
f.tb_crc = ProtoField.uint32("ecpair.tb.crc", "CRC-32", base.HEX)
f.tb_crc_ok = ProtoField.bool("ecpair.tb.crc_ok", "CRC-32 correct")
f.tb_frame_length = ProtoField.uint16("ecpair.tb.frame_length", "Bridged frame length")

local ebad = ProtoExpert.new("ecpair.tb.bad", "Bridge datagram does not decode", expert.group.MALFORMED, expert.severity.ERROR)
ecpair.experts = { ebad }

local eth_dissector = Dissector.get("eth_withoutfcs")

-- CRC-32 (IEEE 802.3, as zlib) with a table, bit32 of Lua 5.2.
local crc_table = {}
for i = 0, 255 do
    local c = i
    for _ = 1, 8 do
        if bit32.band(c, 1) ~= 0 then c = bit32.bxor(bit32.rshift(c, 1), 0xEDB88320) else c = bit32.rshift(c, 1) end
    end
    crc_table[i] = c
end
local function crc32(tvb, offset, length, crc)
    crc = bit32.bnot(crc or 0)
    for i = offset, offset + length - 1 do
        crc = bit32.bxor(crc_table[bit32.band(bit32.bxor(crc, tvb(i, 1):uint()), 0xFF)], bit32.rshift(crc, 8))
    end
    return bit32.bnot(crc)
end

local function dissect_cmf(tvb, at, length, pinfo, tree)
    local t = tree:add(f.cmf, tvb(at, length))
    if length < 16 then return end
    t:add_le(f.cmf_version, tvb(at + 2, 1))
    local kind = tvb(at + 3, 1):uint()
    t:add_le(f.cmf_kind, tvb(at + 3, 1))
    t:add_le(f.cmf_part, tvb(at + 4, 2))
    t:add_le(f.cmf_part_count, tvb(at + 6, 2))
    local offset = tvb(at + 8, 4):le_uint()
    t:add_le(f.cmf_offset, tvb(at + 8, 4))
    t:add_le(f.cmf_cycle_low, tvb(at + 12, 4))
    t:set_text(string.format("CMF %s part %d/%d", section_names[kind] or "?", tvb(at + 4, 2):le_uint(),
                             tvb(at + 6, 2):le_uint()))
    if kind == 6 and offset == 0 and length >= 16 + 16 then
        local a = at + 16
        local ss = t:add(tvb(a, 16), "STANDBY_STATUS")
        local flags = ss:add_le(f.ss_flags, tvb(a, 1))
        for _, field in ipairs({ f.ss_hot, f.ss_forced, f.ss_differs, f.ss_switchover, f.ss_ack, f.ss_main_up,
                                 f.ss_red_up }) do
            flags:add_le(field, tvb(a, 1))
        end
        ss:add(f.ss_mac, tvb(a + 2, 6))
        ss:add_le(f.ss_ack_cycle, tvb(a + 8, 4))
        ss:add_le(f.ss_epoch, tvb(a + 12, 4))
        return
    end
    if kind ~= 1 or offset ~= 0 or length < 16 + 68 then return end
    local h = at + 16
    local version = tvb(h, 1):uint()
    local header = t:add(tvb(h, length - 16), "HEADER")
    header:add_le(f.cmf_header_version, tvb(h, 1))
    header:add_le(f.cmf_master_state, tvb(h + 1, 1))
    local flags = header:add_le(f.cmf_flags, tvb(h + 2, 2))
    flags:add_le(f.cmf_ring_broken, tvb(h + 2, 2))
    flags:add_le(f.cmf_handoff, tvb(h + 2, 2))
    header:add_le(f.cmf_cycle, tvb(h + 4, 8))
    header:add_le(f.cmf_slave_count, tvb(h + 12, 2))
    header:add_le(f.cmf_header_parts, tvb(h + 14, 2))
    header:add_le(f.cmf_ssi_size, tvb(h + 16, 4))
    header:add_le(f.cmf_inputs_size, tvb(h + 20, 4))
    header:add_le(f.cmf_pd_out_size, tvb(h + 24, 4))
    header:add_le(f.cmf_pd_in_size, tvb(h + 28, 4))
    local p = header:add(tvb(h + 32, 28), "Pair parameters")
    p:add_le(f.cmf_eni_hash, tvb(h + 32, 8))
    p:add_le(f.cmf_cycle_time, tvb(h + 40, 8))
    p:add_le(f.cmf_max_acyc, tvb(h + 56, 2))
    p:add_le(f.cmf_param_flags, tvb(h + 58, 1))
    header:add_le(f.cmf_fingerprint, tvb(h + 60, 8))
    if version >= 2 and length >= 16 + 92 then
        header:add_le(f.cmf_epoch, tvb(h + 68, 4))
        header:add_le(f.cmf_handoff_cycle, tvb(h + 72, 8))
        header:add_le(f.cmf_slaves_reached, tvb(h + 80, 2))
        header:add(f.cmf_sender_mac, tvb(h + 82, 6))
        header:add_le(f.cmf_send_offset, tvb(h + 88, 4))
    end
    pinfo.cols.info:append(string.format(" [CMF cycle %s, %s]", tvb(h + 4, 8):le_uint64(),
                                         state_names[tvb(h + 1, 1):uint()] or "?"))
end

local function dissect_bridge(tvb, at, length, pinfo, tree)
    local t = tree:add(f.tb, tvb(at, length))
    if length < 24 then
        t:add_proto_expert_info(ebad, "shorter than the 24-byte header")
        return
    end
    local kind = tvb(at + 3, 1):uint()
    local used = tvb(at + 4, 2):le_uint()
    local count = tvb(at + 6, 1):uint()
    t:add_le(f.tb_version, tvb(at + 2, 1))
    t:add_le(f.tb_kind, tvb(at + 3, 1))
    t:add_le(f.tb_length, tvb(at + 4, 2))
    t:add_le(f.tb_frames, tvb(at + 6, 1))
    t:add_le(f.tb_session, tvb(at + 8, 4))
    t:add_le(f.tb_sequence, tvb(at + 12, 4))
    t:add_le(f.tb_backlog, tvb(at + 16, 2))
    t:add_le(f.tb_crc, tvb(at + 20, 4))
    t:set_text(string.format("TAP bridge %s, %d frame(s), sequence %d", bridge_kinds[kind] or "?", count,
                             tvb(at + 12, 4):le_uint()))
    if used > length - 24 then
        t:add_proto_expert_info(ebad, "payload length beyond the datagram")
        return
    end
    local crc = crc32(tvb, at + 24, used, crc32(tvb, at, 20))
    local ok = crc == tvb(at + 20, 4):le_uint()
    t:add(f.tb_crc_ok, ok)
    if not ok then
        t:add_proto_expert_info(ebad, "CRC-32 mismatch")
        return
    end
    pinfo.cols.info:append(string.format(" [bridge %s %d frame(s)]", bridge_kinds[kind] or "?", count))
    local p = at + 24
    local stop = p + used
    while p + 2 <= stop do
        local n = tvb(p, 2):le_uint()
        if n < 14 or p + 2 + n > stop then
            t:add_proto_expert_info(ebad, "bad bridged frame length")
            return
        end
        t:add_le(f.tb_frame_length, tvb(p, 2))
        eth_dissector:call(tvb(p + 2, n):tvb(), pinfo, t)
        p = p + 2 + n
    end
end

function ecpair.dissector(tvb, pinfo, tree)
    if tvb:len() < 16 then return end
    local at = 12
    local ether_type = tvb(at, 2):uint()
    if ether_type == 0x8100 and tvb:len() >= 20 then
        at = at + 4
        ether_type = tvb(at, 2):uint()
    end
    if ether_type ~= 0x88A4 then return end
    at = at + 2
    local ecat_length = bit32.band(tvb(at, 2):le_uint(), 0x07FF)
    if bit32.rshift(tvb(at, 2):le_uint(), 12) ~= 1 then return end
    at = at + 2
    local stop = math.min(tvb:len(), at + ecat_length)
    local subtree = nil
    while at + 12 <= stop do
        local cmd = tvb(at, 1):uint()
        local adp = tvb(at + 2, 2):le_uint()
        local ado = tvb(at + 4, 2):le_uint()
        local word = tvb(at + 6, 2):le_uint()
        local length = bit32.band(word, 0x07FF)
        if at + 12 + length > stop then return end
        local data = at + 10
        if cmd == 0 and adp == 0 and length >= 2 then
            local m0, m1 = tvb(data, 1):uint(), tvb(data + 1, 1):uint()
            if ado == CMF_ADO and m0 == 0x43 and m1 == 0x4D then
                subtree = subtree or tree:add(ecpair, tvb())
                dissect_cmf(tvb, data, length, pinfo, subtree)
            elseif ado == BRIDGE_ADO and m0 == 0x54 and m1 == 0x42 then
                subtree = subtree or tree:add(ecpair, tvb())
                dissect_bridge(tvb, data, length, pinfo, subtree)
            end
        end
        at = data + length + 2
        if bit32.band(word, 0x8000) == 0 then break end
    end
end

register_postdissector(ecpair)
