#pragma once
// `ecpairctl status`: one member as a table (or one JSON object with
// --json); with two --socket the pair view (pair_view.hpp).

#include <vector>

#include "daemon_connection.hpp"
#include "pair_view.hpp"

namespace ecpair::ctl {

// Asks every socket for its status; members that do not answer carry the reason.
std::vector<PairMember> fetch_members(const std::vector<std::string>& sockets, std::uint32_t variables = 0);

}  // namespace ecpair::ctl
