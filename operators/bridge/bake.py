"""The bake: an ocean's meshes for a range of frames written into a USD file, and the ocean
switched to play them with a Mesh Sequence Cache modifier, so the file renders those frames
where no script runs (a farm that blocks Python, the extension not installed).

First each frame is built as a render builds it (`Bake.step`, one frame at a time, so the
operator can run it from the interface and Esc cancel it between frames): the frame handler
builds the render grid for the scene camera (from the scene as the viewport evaluates it),
keeps the mesh's arrays in a folder beside the target (`keep`) and records what our material is
given (`progress`): the inputs that change are keyed afterwards, the slope layer's images saved
as numbered EXR files; the water body's material and its godrays' caustic tile alike. Then
Blender's own USD exporter steps through the frames as a render does, and the frame handler
writes it each kept mesh (`kept`): the exporter writes them with the attributes the material
reads (the projector UV map under its own name, foam, detail); not their normals, which Blender
computes alike from the positions (2.5 MB a frame at 257x513 instead of 8.5). The exporter
samples a mesh per frame only for objects that change with time, so the ocean carries a
modifier of ours whose output depends on the scene time (and moves nothing) while it writes.
Everything is written beside its target and renamed onto it only when whole, and the ocean is
switched only then: a failed or cancelled bake leaves it live.
"""

import os
import shutil
import tempfile

import bpy

from ...shaders import water
from . import ahead, material_inputs, scene, shot
from .bake_play import play
from .bake_record import SCRATCH, Recording, folder_of, kept_path
from .baked import baked_companions, body_material, free, is_copy
from .state import RUNTIME

TIMER = "Projected Grid Bake Time"  # the node group that makes the exporter sample each frame


def check(the_scene, view_layer, obj, filepath, frame_start, frame_end):
    """The bake's inputs, or ValueError naming the one that is wrong. Returns the absolute path
    of the file to write."""
    if obj is None or obj.type != "MESH" or not obj.projgrid.is_ocean:
        raise ValueError("object: select an ocean to bake")
    if not scene.writable(obj):
        raise ValueError(f"object: {obj.name!r} is linked or overridden from a library; bake "
                         "it in its own file")
    if not scene.owns(obj.data):
        raise ValueError(f"object: {obj.name!r} draws a mesh that is not ours; Add Ocean makes "
                         "a new ocean")
    if is_copy(obj):
        raise ValueError(f"object: {obj.name!r} is a duplicate still sharing another ocean's "
                         "companions and material; Back to Live on it first")
    if any(app.needs_stand_in for app in scene.appearances(the_scene, only=obj)):
        raise ValueError(f"object: {obj.name!r} shows more than once or inside a collection "
                         "instance; bake it where it shows once")
    if not obj.visible_get(view_layer=view_layer):
        raise ValueError(f"object: {obj.name!r} is hidden; show it to bake it")
    if frame_start > frame_end:
        raise ValueError(f"frame_start: {frame_start} is after frame_end {frame_end}")
    if frame_start < the_scene.frame_start or frame_end > the_scene.frame_end:
        raise ValueError(f"frame_start, frame_end: {frame_start}-{frame_end} is outside the "
                         f"scene's frames {the_scene.frame_start}-{the_scene.frame_end}")
    cameras = {shot.scene_camera(the_scene, frame=f) for f in range(frame_start, frame_end + 1)}
    if None in cameras:
        raise ValueError("camera: the scene has no camera to bake the ocean for")
    if len(cameras) > 1:
        raise ValueError(f"frame_end: timeline markers switch between cameras "
                         f"{sorted(c.name for c in cameras)} within frames "
                         f"{frame_start}-{frame_end}; bake each camera's frames apart")
    if filepath.startswith("//") and not bpy.data.filepath:
        raise ValueError(f"filepath: {filepath!r} is relative to the .blend, which is not saved "
                         "yet; save it first or give a full path")
    path = bpy.path.abspath(filepath)
    if not path.lower().endswith((".usd", ".usdc", ".usda")):
        raise ValueError(f"filepath: {filepath!r} is not a USD file (.usdc, .usd or .usda)")
    folder = os.path.dirname(path) or "."
    try:
        os.makedirs(folder, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=folder):
            pass
    except OSError as err:
        raise ValueError(f"filepath: cannot write in {folder!r} ({err.strerror})") from None
    return path


def bake(context, obj, filepath, frame_start, frame_end):
    """Write frames frame_start..frame_end of ocean `obj` into `filepath` and switch it to play
    them, at once (`Bake` step by step); returns (the file's absolute path, a warning or
    None). Raises ValueError (bad input) or RuntimeError (the export failed); in both cases the
    ocean is live (an earlier bake of it undone) and the scene as it was."""
    job = Bake(context, obj, filepath, frame_start, frame_end)
    while job.step():
        pass
    return job.finish()


class Bake:
    """A bake in steps, so that the operator runs it frame by frame in the interface and Esc
    cancels it between frames. `step` builds one frame's render grid for the scene camera (the
    frame handler records what our material is given, `progress`, and keeps the mesh's arrays
    in a folder beside the target, `keep`); `finish` has Blender's USD exporter write the kept
    meshes (it blocks the interface, but builds nothing) and switches the ocean to play the
    file; `cancel` leaves the ocean live and nothing on disk. Any failure does as `cancel`
    and raises."""

    def __init__(self, context, obj, filepath, frame_start, frame_end):
        self.context, self.obj = context, obj
        self.scene, self.view_layer = context.scene, context.view_layer
        self.path = check(self.scene, self.view_layer, obj, filepath, frame_start, frame_end)
        self.relative = filepath.startswith("//")
        free(obj)  # a bake again: the frames are built from the live sea
        self.frame = self.scene.frame_current
        mat, body = material_inputs.material_of(obj.data), body_material(obj)
        folder = folder_of(self.path)
        self.recording = Recording(
            frame_start, frame_end, obj.name, tempfile.mkdtemp(dir=folder),
            _animated(mat.node_tree) if mat is not None else set(),
            body_animated=_animated(body.node_tree) if body is not None else set())
        self.next = frame_start
        RUNTIME.baking = self.recording
        try:
            self.recording.frames = tempfile.mkdtemp(dir=folder, prefix=".projgrid-frames-")
            ahead.finish()
            context.window_manager.progress_begin(frame_start, frame_end)
        except BaseException:
            self._close()
            raise

    @property
    def done(self):
        """The share of the frames built."""
        first, last = self.recording.first, self.recording.last
        return (self.next - first) / (last - first + 1)

    def step(self):
        """Build the next frame; returns whether frames are left to build."""
        try:
            RUNTIME.state(self.obj).key = None  # built even if nothing changed since
            self.scene.frame_set(self.next)
            if self.recording.error:
                raise RuntimeError(self.recording.error)
            if not os.path.exists(kept_path(self.recording, self.next)):
                why = RUNTIME.state(self.obj).message or "the ocean was not rebuilt"
                raise RuntimeError(f"frame {self.next} was not built: {why}")
        except BaseException:
            self._close()
            raise
        self.next += 1
        return self.next <= self.recording.last

    def cancel(self):
        """Stop: the ocean live, the scene at its frame, nothing of the bake on disk."""
        self._close()

    def finish(self):
        """Export the frames built and play them: (the file's path, a warning or None)."""
        recording, the_scene, obj = self.recording, self.scene, self.obj
        stem, ext = os.path.splitext(self.path)
        partial, slopes = f"{stem}.partial{ext}", f"{stem}_slopes"
        frame_range = (the_scene.frame_start, the_scene.frame_end)
        view_layer = self.view_layer
        selected = [o for o in view_layer.objects if o.select_get()]
        active = view_layer.objects.active
        clouds = _spray_cloud(obj, recording)
        exported = [obj, *clouds]
        shown = [(o, o.hide_render, o.hide_viewport, o.hide_select) for o in clouds]
        points = [(m, m.show_render, m.show_viewport) for o in clouds
                  if (m := o.modifiers.get(water.SPRAY_POINTS)) is not None]
        recording.replaying = True
        try:
            for o in exported:  # sampled each frame
                o.modifiers.new(TIMER, "NODES").node_group = _time_group()
            for o in clouds:  # ours: shown and selectable where the exporter sees them
                o.hide_render = o.hide_viewport = o.hide_select = False
            for m, _, _ in points:  # the exporter writes the mesh of puffs, not points
                m.show_render = m.show_viewport = False
            the_scene.frame_start, the_scene.frame_end = recording.first, recording.last
            for o in selected:
                o.select_set(False)
            for o in exported:
                o.select_set(True)
            view_layer.objects.active = obj
            with self.context.temp_override(selected_objects=exported, active_object=obj):
                done = bpy.ops.wm.usd_export(
                    filepath=partial, check_existing=False, selected_objects_only=True,
                    export_animation=True, evaluation_mode="RENDER", export_materials=False,
                    rename_uvmaps=False, export_normals=False, export_custom_properties=False,
                    export_lights=False, export_cameras=False, allow_unicode=False)
            if recording.error:
                raise RuntimeError(recording.error)
            if "FINISHED" not in done or not os.path.exists(partial):
                raise RuntimeError("the USD export did not finish")
            os.replace(partial, self.path)
            if recording.images or recording.tiles:
                if os.path.isdir(slopes):
                    shutil.rmtree(slopes)
                os.replace(recording.slopes, slopes)
                recording.slopes = slopes
        except OSError as err:
            raise RuntimeError(f"writing {self.path!r} failed: {err.strerror}") from None
        finally:
            for o in exported:
                timer = o.modifiers.get(TIMER)
                if timer is not None:
                    o.modifiers.remove(timer)
            for o, hide_render, hide_viewport, hide_select in shown:
                o.hide_render, o.hide_viewport = hide_render, hide_viewport
                o.hide_select = hide_select
            for m, show_render, show_viewport in points:
                m.show_render, m.show_viewport = show_render, show_viewport
            the_scene.frame_start, the_scene.frame_end = frame_range
            for o in view_layer.objects:
                o.select_set(o in selected)
            view_layer.objects.active = active
            self._close(slopes)
        try:
            return self.path, play(obj, self.path, self.relative, recording)
        except Exception as err:
            free(obj)
            raise RuntimeError(f"playing {self.path!r} failed: {err}") from err

    def _close(self, kept=None):
        """The bake's state undone and its scratch removed (the folder `kept` stays), the
        scene back at its frame."""
        recording, path = self.recording, self.path
        if RUNTIME.baking is not recording:
            return
        RUNTIME.baking = None
        self.context.window_manager.progress_end()
        if recording.slopes != kept:  # the frames' images of a bake not made
            shutil.rmtree(recording.slopes, ignore_errors=True)
        if recording.frames:
            shutil.rmtree(recording.frames, ignore_errors=True)
        leftover = os.path.basename(os.path.splitext(path)[0]) + ".partial."  # ours and USD's
        try:
            names = os.listdir(folder_of(path))
        except OSError:
            names = []  # the folder is gone: nothing of ours is left in it
        for name in names:
            full = os.path.join(folder_of(path), name)
            if name.startswith(leftover) and os.path.isfile(full):
                try:
                    os.remove(full)
                except OSError:
                    pass  # the error being raised says more
        for block in (bpy.data.node_groups.get(TIMER), bpy.data.images.get(SCRATCH)):
            if block is not None and block.get(scene.TAG) and block.users == 0:
                bpy.data.batch_remove([block])
        RUNTIME.state(self.obj).key = None
        self.scene.frame_set(self.frame)


def _spray_cloud(obj, recording):
    """[the spray's companion] if the bake kept puffs for it to write, else []."""
    cloud = obj.projgrid.spray_cloud
    return [cloud] if recording.spray and cloud in baked_companions(obj) else []


def _animated(tree):
    """The data paths of `tree` that drivers or keyframes animate already."""
    data = tree.animation_data
    if data is None:
        return set()
    return {d.data_path for d in data.drivers} | {c.data_path for c in scene.bag_curves(tree)}


def _time_group():
    """A node group whose output depends on the scene time and equals its input."""
    group = bpy.data.node_groups.get(TIMER)
    if group is not None and group.get(scene.TAG):
        return group
    group = bpy.data.node_groups.new(TIMER, "GeometryNodeTree")
    group[scene.TAG] = True
    group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    nodes, links = group.nodes, group.links
    given, out = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")
    time = nodes.new("GeometryNodeInputSceneTime")
    move = nodes.new("GeometryNodeSetPosition")
    zero = nodes.new("ShaderNodeVectorMath")
    zero.operation = "SCALE"
    zero.inputs[0].default_value = (0.0, 0.0, 0.0)
    links.new(time.outputs["Seconds"], zero.inputs["Scale"])
    links.new(given.outputs[0], move.inputs["Geometry"])
    links.new(zero.outputs["Vector"], move.inputs["Offset"])
    links.new(move.outputs[0], out.inputs[0])
    return group
