#pragma once

namespace surgical_sim::core {

/// Fixed dimensions of the active trocar and its instrument. This is the one place these numbers
/// live: urdf/active_trocar.urdf is written from TrocarGeometry::chendebPrototype() (see the
/// comment at the top of the URDF) and test/core/haptics/trocar_urdf_test.cpp checks that the URDF
/// chain equals TrocarKinematics.
///
/// Frames: F = trocar frame (tf id `trocar`), origin at the fulcrum O (the incision point), z along
/// the cannula pointing into the patient. The shaft passes through O for every configuration.
/// Tool-tip convention: the tool tip T lies on the shaft axis at depth
///   d = insertion + tip_offset   [m]
/// below the fulcrum, so with insertion = 0 the tip sits tip_offset beyond the fulcrum (just out of
/// the cannula). The instrument shaft spans depths [d - shaft_length, d]; T is the distal end of
/// the shaft, at the jaw hinge (grip does not move T).
///
/// There are no silent defaults: a default-constructed geometry holds NaN and fails validation.
struct TrocarGeometry {
  double tip_offset;       ///< tip depth below the fulcrum at insertion 0 [m], in [0, shaft_length]
  double shaft_length;     ///< instrument shaft length [m], > 0 (prototype 0.400)
  double shaft_diameter;   ///< instrument shaft diameter [m], > 0 (prototype 0.005)
  double cradle_diameter;  ///< cradle ("berceau") diameter [m], > 0 (prototype 0.100)
  double jaw_length;       ///< jaw length beyond the hinge [m], > 0 (our choice 0.015)

  TrocarGeometry();

  /// Chendeb 2007 §5.3–5.4 numbers: tip_offset 0.020 m (our choice: with the 0.30 m travel the
  /// shaft crosses the fulcrum over the whole travel), shaft 0.400 m x Ø0.005 m, cradle Ø0.100 m,
  /// jaws 0.015 m.
  static TrocarGeometry chendebPrototype();
};

/// @throws std::invalid_argument naming "trocar.tip_offset", "trocar.shaft_length",
/// "trocar.shaft_diameter", "trocar.cradle_diameter" or "trocar.jaw_length" with unit and range.
void validateTrocarGeometry(const TrocarGeometry& geometry);

}  // namespace surgical_sim::core
