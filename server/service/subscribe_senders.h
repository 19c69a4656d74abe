// The senders of Subscribe streams (subscribe_call.h) that follow runs integrating: live (one
// run here), follow (every run here, and those of other replicas through FollowRelays) and
// relay (a run integrating on another replica: its owner's stream passed on, unchanged; the
// viewer's probe reports go to the owner, which checks and stores them). The replay's sender
// is in replay_stream.h.
#pragma once

#include <memory>

#include "server/service/follow_relays.h"
#include "server/service/subscribe_call.h"

namespace mbstream {

// Sends the subscription's events until its one run ended (`follow`: until the server
// stops), the viewer left or said goodbye. `relays` (follow, shared store) are stopped with
// the stream. `contacts`: frames keep their contacts (SubscribeRequest.Start.contacts).
std::unique_ptr<SubscribeSender> NewLiveSender(bool follow, int max_batch, bool contacts,
                                               std::unique_ptr<FollowRelays> relays);

// Connects to `owner`'s replica and relays its stream for `start` (on a thread of its own,
// as gRPC's blocking client needs; it ends with the stream). The owner gone: `closing` (the
// viewer reconnects) and UNAVAILABLE.
std::unique_ptr<SubscribeSender> NewRelaySender(SubscribeCall& call, v1::RunInfo owner,
                                                const v1::SubscribeRequest& start);

}  // namespace mbstream
