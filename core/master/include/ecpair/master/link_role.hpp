#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace ecpair::master {

// The two adapters of a master (design.md §1): MAIN faces slave 1's port 0,
// RED faces the other end of the ring (in a pair: the partner's MAIN).
enum class LinkRole : std::uint8_t { Main = 0, Red = 1 };

inline std::string_view to_string(LinkRole role) { return role == LinkRole::Main ? "MAIN" : "RED"; }
inline LinkRole other(LinkRole role) { return role == LinkRole::Main ? LinkRole::Red : LinkRole::Main; }
// The link's slot in per-link arrays (MAIN 0, RED 1).
inline std::size_t index(LinkRole role) { return static_cast<std::size_t>(role); }

}  // namespace ecpair::master
