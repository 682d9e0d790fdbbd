#pragma once
// 128-bit unsigned integer (a GCC/Clang extension), for exact integer sums and Lemire's method.
namespace granboltz {
__extension__ typedef unsigned __int128 uint128;
}
