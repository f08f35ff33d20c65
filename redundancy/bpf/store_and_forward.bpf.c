// SPDX-License-Identifier: GPL-2.0-only
/* The INACTIVE's store-and-forward inside the kernel (design.md §1, §2, §4):
 * the same decisions as StoreAndForward (redundancy/src/store_and_forward.cpp),
 * on tc ingress (tcx) of both of the INACTIVE's links.
 *
 *   not enabled (this master is ACTIVE) -> pass to the host, untouched
 *   larger than any frame, or not a valid datagram frame -> count, drop
 *   not EtherType 0x88A4 -> count, pass to the host (not ours to forward)
 *   leave by the other link if it is up, else back out of the arrival link
 *   the forwarding bit of the leaving link already set -> count, drop
 *   first pass (neither bit): fill MASTER_PD_IN / STANDBY_STATUS, WKC +1,
 *                             the other CMF datagrams WKC +2; a TAP bridge
 *                             POLL gets the answer user space prepared, WKC +1
 *   set the bit, redirect to the leaving link's egress, count
 *
 * User space still sees every arriving frame (its AF_PACKET socket gets it
 * before tc ingress runs) and mirrors it there, off this path. */
#include <linux/bpf.h>
#include <linux/pkt_cls.h>
#include <bpf/bpf_helpers.h>

#include "store_and_forward_maps.h"

char LICENSE[] SEC("license") = "GPL";

struct {
    __uint(type, BPF_MAP_TYPE_ARRAY);
    __uint(max_entries, ECPAIR_KFWD_CONTROL_KEYS);
    __type(key, __u32);
    __type(value, __u32);
} control SEC(".maps");

struct {
    __uint(type, BPF_MAP_TYPE_ARRAY);
    __uint(max_entries, 2);
    __type(key, __u32);
    __type(value, struct ecpair_kfwd_answer);
} answer SEC(".maps");

struct {
    __uint(type, BPF_MAP_TYPE_PERCPU_ARRAY);
    __uint(max_entries, ECPAIR_KFWD_COUNTERS);
    __type(key, __u32);
    __type(value, __u64);
} counters SEC(".maps");

/* The TAP bridge's prepared answers and the slot the next poll takes
 * (store_and_forward_maps.h says how user space and the program share them). */
struct ecpair_kfwd_bridge_answer bridge_answers[ECPAIR_KFWD_BRIDGE_SLOTS];
__u32 bridge_next;

/* Wire constants (core/wire/constants.hpp, redundancy/cmf_format.hpp). */
#define ETHER_HEADER 14
#define VLAN_TAG 4
#define MAX_FRAME_VLAN 1518
#define ETHERTYPE_VLAN 0x8100
#define ETHERTYPE_ETHERCAT 0x88A4
#define ECAT_HEADER 2
#define ECAT_TYPE_DATAGRAMS 1
#define DATAGRAM_HEADER 10
#define DATAGRAM_OVERHEAD 12
#define LENGTH_MASK 0x07FF
#define MORE_BIT 0x8000
/* At least 12 bytes each in at most 1518 - 16: 125 datagrams fit a frame. */
#define MAX_DATAGRAMS 128
#define SOURCE_MAC_BYTE0 6
#define FORWARDED_MAIN_BIT 0x04
#define FORWARDED_RED_BIT 0x80
#define CMD_NOP 0
#define MASTER_RED_ADO 0x4155
#define CMF_SEGMENT_HEADER 16
#define CMF_FORMAT_VERSION 2
#define CMF_KIND_HEADER 1
#define CMF_KIND_MASTER_PD_IN 5
#define CMF_KIND_STANDBY_STATUS 6
#define CMF_READ_WKC 2
#define CMF_WRITE_WKC 1
#define MAX_COPY_CHUNKS 24 /* 24 * 64 >= 1486, the largest datagram data */
/* The TAP bridge (tap_bridge/bridge_datagram.hpp, WIRE_FORMAT.md §11). */
#define BRIDGE_ADO 0x4254
#define BRIDGE_HEADER_PREFIX 16 /* magic, version, kind, ..., session, sequence */
#define BRIDGE_HEADER 24
#define BRIDGE_VERSION 1
#define BRIDGE_KIND_POLL 2

enum link { MAIN = 0, RED = 1 };

static __always_inline void count(__u32 which) {
    __u64* c = bpf_map_lookup_elem(&counters, &which);
    if (c) *c += 1;
}

static __always_inline __u32 control_value(__u32 key) {
    __u32* v = bpf_map_lookup_elem(&control, &key);
    return v ? *v : 0;
}

static __always_inline int load_u16le(struct __sk_buff* skb, __u32 off, __u16* out) {
    __u8 b[2];
    if (bpf_skb_load_bytes(skb, off, b, 2) < 0) return -1;
    *out = (__u16)(b[0] | (b[1] << 8));
    return 0;
}

static __always_inline int add_wkc(struct __sk_buff* skb, __u32 off, __u16 increment) {
    __u16 wkc;
    if (load_u16le(skb, off, &wkc) < 0) return -1;
    wkc += increment;
    __u8 b[2] = {(__u8)wkc, (__u8)(wkc >> 8)};
    return bpf_skb_store_bytes(skb, off, b, 2, 0);
}

/* Copies bytes[from, from + n) to the frame at `to`, chunk by chunk: the
 * verifier must see a bounded size and source range for every store, so
 * sources are checked against `limit` and masked with `mask` (bytes has
 * mask + 1 + one chunk of room). Inlined: mask and limit are constants. */
static __always_inline int copy_to_frame(struct __sk_buff* skb, __u32 to, const __u8* bytes, __u32 from, __u32 n,
                                         __u64 limit, __u64 mask) {
    for (__u32 c = 0; c < MAX_COPY_CHUNKS; c++) {
        const __u32 done = c * ECPAIR_KFWD_COPY_CHUNK;
        if (done >= n) break;
        __u32 chunk = n - done;
        if (chunk > ECPAIR_KFWD_COPY_CHUNK) chunk = ECPAIR_KFWD_COPY_CHUNK;
        __u64 src = (__u64)from + done;
        if (src >= limit) return -1;
        // Bounds the verifier can follow (clang may fold the comparisons above away).
        asm volatile("" : "+r"(src));
        src &= mask;
        __u64 size = chunk;
        asm volatile("" : "+r"(size));
        if (size == 0 || size > ECPAIR_KFWD_COPY_CHUNK) return -1;
        if (bpf_skb_store_bytes(skb, to + done, &bytes[src], size, 0) < 0) return -1;
    }
    return 0;
}

/* The INACTIVE's part of a CMF datagram at `off` with `len` data bytes
 * (process_as_inactive in cmf_inactive.cpp); any other datagram is left alone.
 * A global function: the verifier checks it once, not once per datagram. */
__attribute__((noinline)) int process_datagram(struct __sk_buff* skb, __u32 off, __u32 len, __u32 slot) {
    slot &= 1;
    const struct ecpair_kfwd_answer* a = bpf_map_lookup_elem(&answer, &slot);
    if (!a) return 0;
    __u8 h[DATAGRAM_HEADER];
    if (bpf_skb_load_bytes(skb, off, h, sizeof(h)) < 0) return 0;
    const __u16 adp = (__u16)(h[2] | (h[3] << 8));
    const __u16 ado = (__u16)(h[4] | (h[5] << 8));
    if (h[0] != CMD_NOP || adp != 0 || ado != MASTER_RED_ADO || len < CMF_SEGMENT_HEADER) return 0;
    __u8 s[CMF_SEGMENT_HEADER];
    const __u32 data = off + DATAGRAM_HEADER;
    if (bpf_skb_load_bytes(skb, data, s, sizeof(s)) < 0) return 0;
    if (s[0] != 'C' || s[1] != 'M' || s[2] != CMF_FORMAT_VERSION) return 0;
    const __u8 kind = s[3];
    if (kind < CMF_KIND_HEADER || kind > CMF_KIND_STANDBY_STATUS) return 0;
    const __u16 part = (__u16)(s[4] | (s[5] << 8));
    const __u16 part_count = (__u16)(s[6] | (s[7] << 8));
    if (part >= part_count) return 0;
    const __u32 wkc_at = data + len;
    if (kind != CMF_KIND_MASTER_PD_IN && kind != CMF_KIND_STANDBY_STATUS) {
        return add_wkc(skb, wkc_at, CMF_READ_WKC);
    }
    const __u32 offset = (__u32)s[8] | ((__u32)s[9] << 8) | ((__u32)s[10] << 16) | ((__u32)s[11] << 24);
    const __u32 base = kind == CMF_KIND_STANDBY_STATUS ? 0 : ECPAIR_KFWD_STATUS_SIZE;
    __u32 size = kind == CMF_KIND_STANDBY_STATUS ? ECPAIR_KFWD_STATUS_SIZE : a->pd_in_size;
    if (size > ECPAIR_KFWD_PD_IN_MAX) size = ECPAIR_KFWD_PD_IN_MAX;
    if (offset < size) {
        __u32 n = size - offset;
        const __u32 payload = len - CMF_SEGMENT_HEADER;
        if (n > payload) n = payload;
        if (copy_to_frame(skb, data + CMF_SEGMENT_HEADER, a->bytes, base + offset, n,
                          ECPAIR_KFWD_STATUS_SIZE + ECPAIR_KFWD_PD_IN_MAX, ECPAIR_KFWD_ANSWER_BYTES - 1) < 0) {
            return -1;
        }
    }
    return add_wkc(skb, wkc_at, CMF_WRITE_WKC);
}

/* A TAP bridge POLL at `off` with `len` data bytes gets the answer user
 * space prepared (BridgeChannel::prepare_answers): the one its other copy
 * claimed already, else the slot bridge_next names if it is ready, of this
 * size and not yet claimed. Without one the poll goes on unanswered (the
 * ACTIVE counts it). Any other datagram is left alone. */
__attribute__((noinline)) int answer_bridge_poll(struct __sk_buff* skb, __u32 off, __u32 len) {
    __u8 h[DATAGRAM_HEADER + BRIDGE_HEADER_PREFIX];
    if (len < BRIDGE_HEADER || len > ECPAIR_KFWD_BRIDGE_DATA_MAX) return 0;
    if (bpf_skb_load_bytes(skb, off, h, sizeof(h)) < 0) return 0;
    const __u16 adp = (__u16)(h[2] | (h[3] << 8));
    const __u16 ado = (__u16)(h[4] | (h[5] << 8));
    if (h[0] != CMD_NOP || adp != 0 || ado != BRIDGE_ADO) return 0;
    const __u8* b = &h[DATAGRAM_HEADER];
    if (b[0] != 'T' || b[1] != 'B' || b[2] != BRIDGE_VERSION || b[3] != BRIDGE_KIND_POLL) return 0;
    const __u32 session = (__u32)b[8] | ((__u32)b[9] << 8) | ((__u32)b[10] << 16) | ((__u32)b[11] << 24);
    const __u32 sequence = (__u32)b[12] | ((__u32)b[13] << 8) | ((__u32)b[14] << 16) | ((__u32)b[15] << 24);
    const __u64 id = ((__u64)session << 32) | sequence;
    if (id == 0) return 0;  // indistinguishable from "not claimed"

    struct ecpair_kfwd_bridge_answer* chosen = 0;
    for (__u32 i = 0; i < ECPAIR_KFWD_BRIDGE_SLOTS; i++) {
        struct ecpair_kfwd_bridge_answer* a = &bridge_answers[i];
        if (*(volatile __u32*)&a->ready && *(volatile __u64*)&a->claimed_by == id && a->size == len) {
            chosen = a;  // the other copy of this poll was answered from it
            break;
        }
    }
    if (!chosen) {
        struct ecpair_kfwd_bridge_answer* a = &bridge_answers[*(volatile __u32*)&bridge_next & (ECPAIR_KFWD_BRIDGE_SLOTS - 1)];
        if (*(volatile __u32*)&a->ready && a->size == len && __sync_val_compare_and_swap(&a->claimed_by, 0, id) == 0) {
            chosen = a;
        }
    }
    if (!chosen) return 0;
    const __u32 data = off + DATAGRAM_HEADER;
    if (copy_to_frame(skb, data, chosen->data, 0, len, ECPAIR_KFWD_BRIDGE_DATA_MAX, ECPAIR_KFWD_BRIDGE_DATA_BYTES - 1) < 0) {
        return -1;
    }
    return add_wkc(skb, data + len, 1);
}

SEC("tc")
int ecpair_store_and_forward(struct __sk_buff* skb) {
    if (control_value(ECPAIR_KFWD_ENABLED) == 0) return TC_ACT_OK;
    const __u32 if_main = control_value(ECPAIR_KFWD_IFINDEX_MAIN);
    const __u32 if_red = control_value(ECPAIR_KFWD_IFINDEX_RED);
    enum link arrived;
    if (skb->ifindex == if_main) {
        arrived = MAIN;
    } else if (skb->ifindex == if_red) {
        arrived = RED;
    } else {
        return TC_ACT_OK;  // not one of ours
    }

    const __u32 size = skb->len;
    if (size > MAX_FRAME_VLAN || size < ETHER_HEADER) goto damaged;
    __u8 type_bytes[2];
    if (bpf_skb_load_bytes(skb, 12, type_bytes, 2) < 0) goto damaged;
    __u16 type = (__u16)((type_bytes[0] << 8) | type_bytes[1]);
    __u32 ecat = ETHER_HEADER;
    if (type == ETHERTYPE_VLAN) {
        if (size < ETHER_HEADER + VLAN_TAG) goto damaged;
        if (bpf_skb_load_bytes(skb, 16, type_bytes, 2) < 0) goto damaged;
        type = (__u16)((type_bytes[0] << 8) | type_bytes[1]);
        ecat += VLAN_TAG;
    }
    if (type != ETHERTYPE_ETHERCAT) {
        count(ECPAIR_KFWD_DROPPED_NON_ETHERCAT);
        return TC_ACT_OK;
    }
    __u16 word;
    if (size < ecat + ECAT_HEADER || load_u16le(skb, ecat, &word) < 0) goto damaged;
    if ((word >> 12) != ECAT_TYPE_DATAGRAMS) goto damaged;

    // Walk the datagrams by their own Len fields until one has M=0 (wire::FrameView::parse).
    __u32 off = ecat + ECAT_HEADER;
    int complete = 0;
    for (int i = 0; i < MAX_DATAGRAMS; i++) {
        if (size < off + DATAGRAM_HEADER || load_u16le(skb, off + 6, &word) < 0) goto damaged;
        const __u32 len = word & LENGTH_MASK;
        if (size < off + DATAGRAM_OVERHEAD + len) goto damaged;
        off += DATAGRAM_OVERHEAD + len;
        if ((word & MORE_BIT) == 0) {
            complete = 1;
            break;
        }
    }
    if (!complete) goto damaged;

    __u8 byte0;
    if (bpf_skb_load_bytes(skb, SOURCE_MAC_BYTE0, &byte0, 1) < 0) goto damaged;
    const int first_pass = (byte0 & (FORWARDED_MAIN_BIT | FORWARDED_RED_BIT)) == 0;
    const enum link onward = arrived == MAIN ? RED : MAIN;
    const int onward_up = control_value(onward == MAIN ? ECPAIR_KFWD_UP_MAIN : ECPAIR_KFWD_UP_RED) != 0;
    const enum link leaving = onward_up ? onward : arrived;
    const __u8 bit = leaving == MAIN ? FORWARDED_MAIN_BIT : FORWARDED_RED_BIT;
    if (byte0 & bit) {
        count(ECPAIR_KFWD_DROPPED_CIRCULATING);
        return TC_ACT_SHOT;
    }
    byte0 |= bit;
    if (bpf_skb_store_bytes(skb, SOURCE_MAC_BYTE0, &byte0, 1, 0) < 0) goto damaged;

    if (first_pass) {
        const __u32 slot = control_value(ECPAIR_KFWD_ANSWER_SLOT);
        off = ecat + ECAT_HEADER;
        for (int i = 0; i < MAX_DATAGRAMS; i++) {
            if (load_u16le(skb, off + 6, &word) < 0) break;
            const __u32 len = word & LENGTH_MASK;
            process_datagram(skb, off, len, slot);
            answer_bridge_poll(skb, off, len);
            off += DATAGRAM_OVERHEAD + len;
            if ((word & MORE_BIT) == 0) break;
        }
    }

    if (leaving == arrived) {
        count(ECPAIR_KFWD_BOUNCED);
    } else {
        count(arrived == MAIN ? ECPAIR_KFWD_FORWARDED_MAIN_TO_RED : ECPAIR_KFWD_FORWARDED_RED_TO_MAIN);
    }
    return bpf_redirect(leaving == MAIN ? if_main : if_red, 0);

damaged:
    count(ECPAIR_KFWD_DROPPED_DAMAGED);
    return TC_ACT_SHOT;
}
