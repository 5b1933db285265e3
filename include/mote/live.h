/* live.h: the live view (issue 25): a small HTTP server inside a run (libmicrohttpd, one thread
 * per connection) that serves a built-in page and a Server-Sent-Events stream of frames, which
 * the page draws. The run publishes a frame when one is due (at most 30 a second of wall clock,
 * at most a tenth of the run's time, and only while a viewer is connected) by copying it into
 * one slot; viewers take the newest frame when they can, so a slow or vanished viewer drops
 * frames and never holds the run up.
 * The page can pause and resume the run; nothing else it sends has an effect. Loopback only
 * unless another address is given; only "/", "/stream", "/pause" and "/resume" exist. */
#ifndef MOTE_LIVE_H
#define MOTE_LIVE_H

#include "mote/buf.h"
#include "mote/core.h"

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

typedef struct mote_live mote_live;

/* Start the server on bind:port (bind NULL: 127.0.0.1; port 0: any free port); the address to
 * open goes into url. Fails with a message (port taken, bad address). */
int mote_live_start(mote_live **live, const char *bind, int port, char url[128], mote_err *err);
void mote_live_stop(mote_live *live);
/* Is a frame due (a viewer connected, and 1/30 s since the last, or ten times what making the
 * last took when that is longer (mote_pace_gap), or `now`)? */
int mote_live_due(mote_live *live, int now);
/* Publish a frame (a JSON object, copied) that took `cost` seconds to make; frames published
 * count from 1. */
void mote_live_publish(mote_live *live, const char *json, size_t len, double cost);
/* Block while the page has paused the run. */
void mote_live_hold(mote_live *live);
/* Frames published, and viewers connected now. */
uint64_t mote_live_frames(mote_live *live);
int mote_live_viewers(mote_live *live);

#endif
