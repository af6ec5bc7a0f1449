#pragma once
// glTF 2.0's numeric codes, as the specification names them (accessor.componentType and
// bufferView.target), for the writers that build a document as JSON.
namespace sweep::assets::detail::gltf_codes {

constexpr int kUnsignedByte = 5121;
constexpr int kUnsignedShort = 5123;
constexpr int kUint = 5125;  // UNSIGNED_INT
constexpr int kFloat = 5126;
constexpr int kArrayBuffer = 34962;

}  // namespace sweep::assets::detail::gltf_codes
