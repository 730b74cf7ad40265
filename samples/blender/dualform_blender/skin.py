"""A mesh object's Armature modifier as a Dualform skin, in the object's
own space, so that the library poses the mesh exactly as Blender shows it.

Blender's Armature modifier (linear blend skinning, armature_deform.c)
moves an object-space vertex p to

    sum_b (w_b / c) M_o^-1 M_a P_b R_b^-1 M_a^-1 M_o p

over the deform bones b whose vertex groups hold the vertex with a weight
w_b > 0, c the sum of those weights, M_o and M_a the object's and the
armature's world matrices, R_b the bone's rest matrix and P_b its pose
matrix (both in armature space); a vertex with c <= 1e-4 stays where it is.
As a Dualform skin: joint b's inverse bind matrix is R_b^-1 M_a^-1 M_o and
its world matrix M_o^-1 M_a P_b, and the vertices the modifier leaves alone
are bound to one more joint whose matrices are the identity. The input is
the object's shape-key mix (Blender applies shape keys first): the bind
space in which a corrective key is written.

Preserve Volume (dual quaternion skinning), bone envelopes, the modifier's
vertex-group mask, Multi Modifier, B-Bone segments, and modifiers before
the armature would each move vertices in ways this skin does not
reproduce: they are refused with a message saying what to change.
"""

from __future__ import annotations

from typing import List, Optional

import numpy as np

# armature_deform.c leaves a vertex whose deform weights sum to this or less.
MIN_CONTRIBUTION = 1e-4
# The angle (radians) below which a bone counts as at rest for a driver.
MIN_DRIVER_ANGLE = 1e-3


def _matrix(m) -> np.ndarray:
    return np.array(m, dtype=np.float64)


def armature_modifier(obj):
    """The Armature modifier that poses ``obj`` in the viewport, or None;
    ValueError (the message says what to change) for a setup whose
    deformation the skin would not reproduce exactly."""
    shown = [m for m in obj.modifiers if m.show_viewport]
    armatures = [m for m in shown if m.type == "ARMATURE" and m.object is not None]
    if not armatures:
        return None
    if len(armatures) > 1:
        raise ValueError(f"'{obj.name}' has {len(armatures)} Armature modifiers: Dualform poses "
                         "a mesh by one")
    modifier = armatures[0]
    if shown[0] != modifier:
        raise ValueError(f"the modifier '{shown[0].name}' comes before '{modifier.name}': "
                         "Dualform edits what the Armature modifier is given (the mesh and its "
                         "shape keys); move the Armature modifier first")
    refused = [
        (modifier.use_deform_preserve_volume,
         "Preserve Volume (dual quaternion skinning) is on: Dualform's corrective is exact for "
         "linear blend skinning; turn Preserve Volume off"),
        (modifier.use_bone_envelopes, "it deforms by bone envelopes: use vertex groups only"),
        (not modifier.use_vertex_groups, "it does not deform by vertex groups: turn them on"),
        (bool(modifier.vertex_group), f"its vertex group '{modifier.vertex_group}' masks it: "
                                      "clear the mask"),
        (modifier.use_multi_modifier, "Multi Modifier is on: turn it off"),
    ]
    for is_refused, reason in refused:
        if is_refused:
            raise ValueError(f"the Armature modifier '{modifier.name}' of '{obj.name}': {reason}")
    return modifier


class ArmatureSkin:
    """``obj``'s skin (``armature_modifier`` must find one) at the
    depsgraph's frame: ``joints`` and ``weights`` (n, K), ``inverse_bind``
    and ``joint_world`` (J, 4, 4) in the object's space, ``bones`` the
    deform bones' names in joint order (a last joint "" holds the vertices
    no deform bone moves, where there are any)."""

    def __init__(self, obj, modifier, depsgraph) -> None:
        self.obj = obj
        self.armature = modifier.object
        deform = [b for b in self.armature.data.bones if b.use_deform]
        segmented = [b.name for b in deform if b.bbone_segments > 1]
        if segmented:
            raise ValueError(f"the bone '{segmented[0]}' of '{self.armature.name}' deforms as a "
                             "B-Bone (segments > 1): Dualform's skin bends each bone rigidly; "
                             "set its segments to 1")
        enveloped = [b.name for b in deform if b.use_envelope_multiply]
        if enveloped:
            raise ValueError(f"the bone '{enveloped[0]}' of '{self.armature.name}' multiplies "
                             "its vertex group by its envelope: turn that off")
        self.bones = [b.name for b in deform]
        joint_of = {b: j for j, b in enumerate(self.bones)}
        group_joint = {g.index: joint_of[g.name] for g in obj.vertex_groups if g.name in joint_of}
        rows = [[(group_joint[g.group], g.weight) for g in v.groups
                 if g.group in group_joint and g.weight > 0.0] for v in obj.data.vertices]
        still = [sum(w for _, w in row) <= MIN_CONTRIBUTION for row in rows]
        if any(still):
            self.bones.append("")
        static = len(self.bones) - 1
        influences = max(1, max(len(row) for row in rows))
        self.joints = np.zeros((len(rows), influences), dtype=np.uint32)
        self.weights = np.zeros((len(rows), influences), dtype=np.float64)
        for v, row in enumerate(rows):
            if still[v]:
                self.joints[v, 0], self.weights[v, 0] = static, 1.0
                continue
            for k, (joint, weight) in enumerate(row):
                self.joints[v, k], self.weights[v, k] = joint, weight
        self.weights /= self.weights.sum(axis=1, keepdims=True)
        armature = self.armature.evaluated_get(depsgraph)
        # Object space to the armature's, as the modifier takes a vertex there.
        self.to_armature = (np.linalg.inv(_matrix(armature.matrix_world))
                            @ _matrix(obj.evaluated_get(depsgraph).matrix_world))
        from_armature = np.linalg.inv(self.to_armature)
        self.inverse_bind = np.stack(
            [np.linalg.inv(_matrix(b.matrix_local)) @ self.to_armature for b in deform]
            + [np.eye(4)] * (len(self.bones) - len(deform)))
        self.joint_world = np.stack(
            [from_armature @ _matrix(armature.pose.bones[b.name].matrix) for b in deform]
            + [np.eye(4)] * (len(self.bones) - len(deform)))
        self._evaluated = armature

    @classmethod
    def of(cls, obj, depsgraph) -> Optional["ArmatureSkin"]:
        """The skin posing ``obj``, or None for a mesh no armature poses."""
        modifier = armature_modifier(obj)
        return None if modifier is None else cls(obj, modifier, depsgraph)

    def blended_linear(self, vertices: np.ndarray) -> np.ndarray:
        """L_v, the 3x3 part of each vertex's blended skinning matrix,
        (len(vertices), 3, 3): how a bind-space move shows in the pose."""
        skinning = (self.joint_world @ self.inverse_bind)[:, :3, :3]
        return np.einsum("vk,vkij->vij", self.weights[vertices],
                         skinning[self.joints[vertices].astype(np.int64)])

    def bone_angle(self, bone: str) -> float:
        """The bone's rotation from its rest pose, in its parent's space
        (radians): what a driver reading its local rotation sees."""
        pose_bone = self._evaluated.pose.bones[bone]
        local = self._evaluated.convert_space(pose_bone=pose_bone, matrix=pose_bone.matrix,
                                              from_space="POSE", to_space="LOCAL")
        w = abs(local.to_quaternion().normalized().w)
        return 2.0 * float(np.arccos(min(w, 1.0)))

    def nearest_turned_bone(self, points: np.ndarray) -> Optional[str]:
        """The deform bone whose head (its joint) lies nearest the points'
        centroid (object space, posed) and, if it stands at rest, the
        nearest ancestor that is turned; None when none is."""
        centroid = points.mean(axis=0)
        from_armature = np.linalg.inv(self.to_armature)
        deform = [b for b in self.bones if b]
        pose_bones = self._evaluated.pose.bones
        heads = np.array([(from_armature @ np.append(_matrix(pose_bones[b].head), 1.0))[:3]
                          for b in deform])
        bone = pose_bones[deform[int(np.argmin(np.linalg.norm(heads - centroid, axis=1)))]]
        while bone is not None and self.bone_angle(bone.name) < MIN_DRIVER_ANGLE:
            bone = bone.parent
        return None if bone is None else bone.name

    def drive_by_angle(self, key, points: np.ndarray) -> List[str]:
        """Adds a driver to ``key``'s value: 0 with the bone nearest the
        points at rest, rising with its angle to 1 at this pose's angle and
        held there beyond (a simple expression: no Python runs it). Returns
        [bone, angle in degrees], or [] when every bone near is at rest."""
        bone = self.nearest_turned_bone(points)
        if bone is None:
            return []
        angle = self.bone_angle(bone)
        curve = key.driver_add("value")
        driver = curve.driver
        driver.type = "SCRIPTED"
        variable = driver.variables.new()
        variable.name = "w"
        variable.type = "TRANSFORMS"
        target = variable.targets[0]
        target.id = self.armature
        target.bone_target = bone
        target.transform_type = "ROT_W"
        target.rotation_mode = "QUATERNION"
        target.transform_space = "LOCAL_SPACE"
        driver.expression = f"clamp(2 * acos(min(abs(w), 1)) / {angle!r}, 0, 1)"
        return [bone, f"{np.degrees(angle):.1f}"]
