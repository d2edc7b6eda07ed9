#pragma once
// Whether the client of a request is still there. cpp-httplib 0.11 does not tell a handler
// about its connection, so the connection's socket is found among the process's descriptors
// by the request's two addresses (unique while the handler runs: the connection stays open
// until it returns), then polled for the peer's close.

#include <httplib.h>

namespace meshd::server {

/// The socket of the connection the request came on, or -1 when it cannot be found.
int connection_socket(const httplib::Request& req);

/// True when the peer has closed its side of the connection (or the connection failed). A
/// client that only half-closes after sending its request reads as gone too.
bool peer_closed(int fd);

}  // namespace meshd::server
