#pragma once
// The observers a config needs (dsmc/observers/observer.hpp), in the order run.cpp schedules them.
#include <memory>
#include <vector>

#include "granboltz/dsmc/config.hpp"
#include "granboltz/dsmc/observers/observer.hpp"

namespace granboltz {

/// `d` must outlive the observers (they keep a reference to it).
std::vector<std::unique_ptr<Observer>> make_observers(const DsmcConfig& d);

}  // namespace granboltz
