"""A shader node tree's values evaluated node by node in Python (a shader cannot be run
without a render): Blender's Math and Vector Math nodes on floats or NumPy arrays, the scene's
inputs (attributes, camera data, geometry, noises) stubbed."""

import numpy as np


def _safe_log(a, b):
    ok = (a > 0.0) & (b > 0.0) & (b != 1.0)
    return np.where(ok, np.log(np.where(ok, a, 2.0)) / np.log(np.where(ok, b, 2.0)), 0.0)


def _safe_pow(a, b):
    ok = ~((a < 0.0) & (b != np.floor(b))) & ((a != 0.0) | (b > 0.0))
    return np.where(ok, np.power(np.where(ok, a, 1.0), b), 0.0)


def _safe_div(a, b):
    return np.where(b != 0.0, a / np.where(b != 0.0, b, 1.0), 0.0)


# Blender's Math node on floats or NumPy arrays (a node's values for many stubbed noise values)
MATH = {
    "ADD": lambda a, b, c: a + b, "SUBTRACT": lambda a, b, c: a - b,
    "MULTIPLY": lambda a, b, c: a * b, "DIVIDE": lambda a, b, c: _safe_div(a, b),
    "MULTIPLY_ADD": lambda a, b, c: a * b + c, "MAXIMUM": lambda a, b, c: np.maximum(a, b),
    "MINIMUM": lambda a, b, c: np.minimum(a, b), "ABSOLUTE": lambda a, b, c: np.abs(a),
    "SQRT": lambda a, b, c: np.sqrt(np.maximum(a, 0.0)),
    "LOGARITHM": lambda a, b, c: _safe_log(a, b), "POWER": lambda a, b, c: _safe_pow(a, b),
    "EXPONENT": lambda a, b, c: np.exp(a), "LESS_THAN": lambda a, b, c: (a < b) * 1.0,
    "COSINE": lambda a, b, c: np.cos(a), "SINE": lambda a, b, c: np.sin(a),
    "GREATER_THAN": lambda a, b, c: (a > b) * 1.0,
}
VECTOR = {
    "ADD": lambda a, b, s: a + b, "SUBTRACT": lambda a, b, s: a - b,
    "MULTIPLY": lambda a, b, s: a * b, "SCALE": lambda a, b, s: a * s,
    "MINIMUM": lambda a, b, s: np.minimum(a, b),
    "NORMALIZE": lambda a, b, s: a / np.linalg.norm(a) if np.linalg.norm(a) else a * 0.0,
}


FACET_RANDOM = (0.3, 0.2)


class Evaluator:
    """Values of a shader node tree's sockets for given group inputs and stubbed scene inputs
    (the nodes a render would feed: attribute, camera data, geometry). `fac`: every noise's
    Fac (a float, or an array: the tree's values for each), or a dict of them by the noise's
    Scale (an unlinked socket's value, rounded to 6 places; None for the rest)."""

    def __init__(self, group_inputs, lod, distance, incoming, attributes=None, fac=0.5,
                 backfacing=0.0):
        self.inputs, self.cache, self.attributes = group_inputs, {}, attributes or {}
        self.stubs = {"ShaderNodeAttribute": {"Fac": lod},
                      "ShaderNodeCameraData": {"View Distance": distance},
                      "ShaderNodeNewGeometry": {"Incoming": np.asarray(incoming, float),
                                                "Normal": np.array([0.0, 0.0, 1.0]),
                                                "Backfacing": backfacing},
                      # the waves' bumps: a flat sea's normal (the glint's sun reach uses it)
                      "ShaderNodeBump": {"Normal": np.array([0.0, 0.0, 1.0])},
                      # the glint facet's cell: its two random values
                      "ShaderNodeTexVoronoi": {"Color": np.array([*FACET_RANDOM, 0.5])},
                      "ShaderNodeTexNoise": {"Fac": fac}}
        self.fac, self.feeds = fac, None

    def _feeding(self, socket):
        """The socket linked into `socket` (one pass over the tree's links: a socket's own
        `links` searches them all at each call)."""
        if self.feeds is None:
            self.feeds = {link.to_socket.as_pointer(): link.from_socket
                          for link in socket.id_data.links}
        return self.feeds[socket.as_pointer()]

    def input(self, socket):
        if socket.is_linked:
            return self.output(self._feeding(socket))
        value = socket.default_value
        return np.array(value[:3], float) if hasattr(value, "__len__") else float(value)

    def output(self, socket):
        key = socket.as_pointer()
        if key not in self.cache:
            self.cache[key] = self._compute(socket.node, socket)
        return self.cache[key]

    def _compute(self, node, socket):
        kind = node.bl_idname
        if kind == "NodeGroupInput":
            return self.inputs[socket.name]
        if kind == "ShaderNodeAttribute" and node.attribute_name in self.attributes:
            return self.attributes[node.attribute_name]
        if kind == "ShaderNodeMix":
            t, a, b = (self.input(next(s for s in node.inputs if s.identifier == k))
                       for k in ("Factor_Float", "A_Float", "B_Float"))
            return a + t * (b - a)
        if kind == "ShaderNodeTexNoise" and isinstance(self.fac, dict):
            scale = node.inputs["Scale"]
            return self.fac.get(None if scale.is_linked else round(scale.default_value, 6),
                                self.fac[None])
        if kind in self.stubs:
            stub = self.stubs[kind]
            return stub[socket.identifier] if socket.identifier in stub else stub[socket.name]
        if kind == "ShaderNodeMath":
            a, b, c = (self.input(s) for s in node.inputs[:3])
            v = MATH[node.operation](a, b, c)
            v = np.clip(v, 0.0, 1.0) if node.use_clamp else v
            return float(v) if np.ndim(v) == 0 else v
        if kind == "ShaderNodeVectorMath":
            a, b = self.input(node.inputs[0]), self.input(node.inputs[1])
            s = self.input(node.inputs["Scale"]) if node.operation == "SCALE" else None
            if node.operation == "DOT_PRODUCT":
                return float(np.dot(a, b))
            if node.operation == "LENGTH":
                return float(np.linalg.norm(a))
            return VECTOR[node.operation](a, b, s)
        if kind == "ShaderNodeSeparateColor":
            return float(self.input(node.inputs[0])[("Red", "Green", "Blue").index(socket.name)])
        if kind == "ShaderNodeSeparateXYZ":
            return float(self.input(node.inputs[0])["XYZ".index(socket.name)])
        if kind == "ShaderNodeCombineXYZ":
            return np.array([self.input(node.inputs[k]) for k in "XYZ"], float)
        raise NotImplementedError(kind)
