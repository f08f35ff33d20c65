/* What the INACTIVE's kernel store-and-forward program (store_and_forward.bpf.c)
 * and its loader (redundancy/src/kernel_forwarding.cpp) share: the maps'
 * keys and values. Plain C: the BPF program and C++ both include it. */
#ifndef ECPAIR_STORE_AND_FORWARD_MAPS_H
#define ECPAIR_STORE_AND_FORWARD_MAPS_H

#ifdef __cplusplus
#include <cstdint>
typedef std::uint64_t ecpair_u64;
typedef std::uint32_t ecpair_u32;
typedef std::uint8_t ecpair_u8;
#else
typedef __u64 ecpair_u64;
typedef __u32 ecpair_u32;
typedef __u8 ecpair_u8;
#endif

/* `control` (array of u32), one key per value so that the link monitor and
 * the cycle thread update theirs without overwriting the other's. */
enum ecpair_kfwd_control_key {
    ECPAIR_KFWD_IFINDEX_MAIN = 0,
    ECPAIR_KFWD_IFINDEX_RED = 1,
    ECPAIR_KFWD_UP_MAIN = 2,   /* 1: frames may leave by MAIN */
    ECPAIR_KFWD_UP_RED = 3,
    ECPAIR_KFWD_ANSWER_SLOT = 4, /* which `answer` entry (0, 1) is complete */
    ECPAIR_KFWD_ENABLED = 5,     /* 1: INACTIVE, forward; 0: pass every frame to the host */
    ECPAIR_KFWD_CONTROL_KEYS = 6,
};

/* `answer` (array of 2): what the INACTIVE writes into every CMF on its first
 * pass. User space writes the slot that is not current, then flips
 * ECPAIR_KFWD_ANSWER_SLOT, so the program never reads half of an update.
 * bytes = STANDBY_STATUS section (16 bytes), then the MASTER_PD_IN section. */
#define ECPAIR_KFWD_STATUS_SIZE 16
#define ECPAIR_KFWD_PD_IN_MAX 4096
#define ECPAIR_KFWD_COPY_CHUNK 64
/* A power of two >= STATUS_SIZE + PD_IN_MAX: the program masks copy sources with it. */
#define ECPAIR_KFWD_ANSWER_BYTES 8192
struct ecpair_kfwd_answer {
    ecpair_u32 pd_in_size;
    ecpair_u32 reserved;
    /* + one chunk of slack: the verifier sees every copy stay inside */
    ecpair_u8 bytes[ECPAIR_KFWD_ANSWER_BYTES + ECPAIR_KFWD_COPY_CHUNK];
};

/* The TAP bridge's answers (the global `bridge_answers`, in .bss: user space
 * reads and writes it through the skeleton's mapping, no system call). User
 * space prepares a sealed ANSWER in a slot ahead of the polls and points
 * `bridge_next` at it; the first poll of exactly that size to pass claims it
 * (claimed_by: 0 -> the poll's session << 32 | sequence, one atomic
 * compare-and-swap), and the poll's other copy finds it by that id and gets
 * the same bytes. User space rewrites only a slot it moved on from (ready 0
 * while it writes); a copy torn by such a rewrite fails the datagram's CRC
 * at the ACTIVE and is dropped there, never delivered. */
#define ECPAIR_KFWD_BRIDGE_SLOTS 4
#define ECPAIR_KFWD_BRIDGE_DATA_MAX 1486
/* A power of two >= BRIDGE_DATA_MAX: the program masks copy sources with it. */
#define ECPAIR_KFWD_BRIDGE_DATA_BYTES 2048
struct ecpair_kfwd_bridge_answer {
    ecpair_u64 claimed_by; /* 0: no poll took it yet */
    ecpair_u32 ready;      /* 1: size and data are complete */
    ecpair_u32 size;       /* data bytes: it answers a poll of exactly this size */
    ecpair_u8 data[ECPAIR_KFWD_BRIDGE_DATA_BYTES + ECPAIR_KFWD_COPY_CHUNK];
};

/* `counters` (per-CPU array of u64), StoreAndForwardCounters' fields. */
enum ecpair_kfwd_counter {
    ECPAIR_KFWD_FORWARDED_MAIN_TO_RED = 0,
    ECPAIR_KFWD_FORWARDED_RED_TO_MAIN = 1,
    ECPAIR_KFWD_BOUNCED = 2,
    ECPAIR_KFWD_DROPPED_CIRCULATING = 3,
    ECPAIR_KFWD_DROPPED_NON_ETHERCAT = 4,
    ECPAIR_KFWD_DROPPED_DAMAGED = 5,
    ECPAIR_KFWD_COUNTERS = 6,
};

#endif
