#pragma once
// Inlining the event loop's helpers matters (15-30 % of the time per event) and GCC's size
// heuristics decline some of them; this forces it for the few functions of the hot path.
#define GRANBOLTZ_HOT [[gnu::always_inline]] inline
