#pragma once
// SHA-256 (FIPS 180-4) for the animation page's Content-Security-Policy, which names each inline script by the
// base64 of its digest.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace rome {

std::array<std::uint8_t, 32> Sha256(std::string_view data);
/// Lower-case hexadecimal of the digest (as sha256sum prints it).
std::string Sha256Hex(std::string_view data);
/// Base64 (RFC 4648, with padding) of the digest, as a CSP 'sha256-...' source takes it.
std::string Sha256Base64(std::string_view data);

}  // namespace rome
