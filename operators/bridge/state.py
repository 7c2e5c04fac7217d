"""What the Blender layer keeps between frames: one typed state per surface, in one runtime."""

from dataclasses import dataclass, field


@dataclass
class SurfaceState:
    """One surface (an ocean drawing itself, or a stand-in of ours drawing one): what the panel
    shows and what the next frame compares against."""

    message: str | None = None  # why the last rebuild was refused
    warning: str | None = None  # what is wrong with the last built sea, and what to change
    hidden: bool = False  # the ocean does not show in the last evaluation: not rebuilt
    vertices: int = 0
    grid: object = None  # the last GridResult, without its float64 surface
    ms: float = 0.0  # the last rebuild's time
    effects: dict | None = None  # {effect: (on, reason)} of the last built frame
    resolution: tuple | None = None
    render: bool = False  # the last build was for a render
    camera: tuple | None = None  # (view, proj) the last build used
    key: tuple | None = None  # every input of the last build: an equal key skips the rebuild
    drawn_by: str | None = None  # on an ocean drawn by a stand-in: the stand-in's name
    generation: int = -1  # the scene structure its companions last followed
    stale: str | None = None  # on a baked ocean: why the frame shown is out of date

    def refused(self, message):
        """Record that no grid was built, and why."""
        self.message, self.warning, self.key = message, None, None
        self.vertices, self.grid, self.ms, self.effects = 0, None, 0.0, None
        return message


@dataclass
class Runtime:
    """The Blender layer's memory of this session: per-surface states keyed by the objects'
    session_uid (stable across renames), whether a render runs, the 3D view the live preview
    follows, and caches that are checked on every use. Cleared when a file is loaded."""

    surfaces: dict = field(default_factory=dict)  # session_uid -> SurfaceState
    rendering: bool = False
    batching: bool = False  # settings being set together (settings.batch): no rebuild each
    live_view: tuple | None = None  # (view, proj) of the 3D view the live preview follows
    baking: object | None = None  # bake_record.Recording of the bake being written
    stand_ins: dict = field(default_factory=dict)  # appearance key -> stand-in's name_full
    object_count: int = -1  # bpy.data.objects' length at the last check for deleted oceans
    scenes: dict = field(default_factory=dict)  # scene session_uid -> scene.SceneCache
    swapped: dict = field(default_factory=dict)  # surface uid -> (surface, viewport mesh)

    def state(self, obj):
        """The state of surface `obj`, made empty on first use."""
        return self.surfaces.setdefault(obj.session_uid, SurfaceState())

    def peek(self, obj):
        """The state of `obj` if it has one."""
        return self.surfaces.get(obj.session_uid)

    def prune(self, alive):
        """Forget the states of objects whose session_uid is not in `alive`."""
        for uid in [u for u in self.surfaces if u not in alive]:
            del self.surfaces[uid]

    def clear(self):
        self.__init__()


RUNTIME = Runtime()
