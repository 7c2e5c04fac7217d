"""Helpers for building shader node trees from code: `Graph` adds a node per call, links the
inputs that are sockets and sets the ones that are values, and returns the output socket. It is
also the maths the look's formulas (projgrid_addon/water_model.py) are built in: its scalar
outputs are `Value`s, on which + - * / add Math nodes."""

import math

TAG = "projgrid_ocean"  # ID property marking the data this extension made (never the user's)


def assign(target, **values):
    """Set each attribute whose value changes by more than 1e-7 or its float32 rounding (in
    any component): every write tags its data-block for a depsgraph update, which runs our
    handlers again, and Blender keeps its floats in single precision, so a value that does not
    change reads back off by up to half its last place (a 2^24th of itself; a change of one
    place is written)."""
    for name, value in values.items():
        current = getattr(target, name)
        pairs = (zip(current, value, strict=True) if hasattr(current, "__len__")
                 else ((current, value),))
        if any(abs(a - b) > max(1e-7, abs(b) * 2.0**-24) for a, b in pairs):
            setattr(target, name, value)


def empty_tree(id_block):
    """The node tree of a new material or world, emptied (nodes are switched on first before
    Blender 5.0; from 5.0 every material and world has them)."""
    if id_block.node_tree is None:
        id_block.use_nodes = True
    id_block.node_tree.nodes.clear()
    return id_block.node_tree


def socket(sockets, key):
    """A socket by index, name, or identifier (the Mix node's inputs share names across types)."""
    if isinstance(key, int) or key in sockets:
        return sockets[key]
    return next(s for s in sockets if s.identifier == key)


class Value:
    """A node's scalar output in arithmetic: each operator adds a Math node."""

    __slots__ = ("graph", "socket")

    def __init__(self, graph, socket_):
        self.graph, self.socket = graph, socket_

    @property
    def node(self):
        return self.socket.node

    def __add__(self, other):
        return self.graph.math("ADD", self, other)

    def __radd__(self, other):
        return self.graph.math("ADD", other, self)

    def __sub__(self, other):
        return self.graph.math("SUBTRACT", self, other)

    def __rsub__(self, other):
        return self.graph.math("SUBTRACT", other, self)

    def __mul__(self, other):
        return self.graph.math("MULTIPLY", self, other)

    def __rmul__(self, other):
        return self.graph.math("MULTIPLY", other, self)

    def __truediv__(self, other):
        return self.graph.math("DIVIDE", self, other)

    def __rtruediv__(self, other):
        return self.graph.math("DIVIDE", other, self)

    def __neg__(self):
        return self.graph.math("MULTIPLY", self, -1.0)


class Graph:
    def __init__(self, tree):
        self.tree = tree
        self.nodes = tree.nodes
        self.links = tree.links
        self.x = 0

    def node(self, kind, inputs=(), **props):
        """Add a node of type `kind`; `inputs` maps input names or indices to sockets or values."""
        node = self.nodes.new(kind)
        node.location = (self.x, 0)
        self.x += 40
        for name, value in props.items():
            setattr(node, name, value)
        for key, value in dict(inputs).items():
            self.set(socket(node.inputs, key), value)
        return node

    def set(self, socket, value):
        if isinstance(value, Value):
            value = value.socket
        if hasattr(value, "is_output"):
            self.links.new(value, socket)
        else:
            socket.default_value = value

    def value(self, socket_):
        """A scalar output socket as a Value."""
        return Value(self, socket_)

    def math(self, operation, *args, clamp=False):
        node = self.node("ShaderNodeMath", enumerate(args), operation=operation, use_clamp=clamp)
        return Value(self, node.outputs[0])

    def vector(self, operation, *args, **named):
        inputs = [*enumerate(args), *named.items()]
        node = self.node("ShaderNodeVectorMath", inputs, operation=operation)
        if operation in ("DOT_PRODUCT", "LENGTH"):
            return Value(self, node.outputs["Value"])
        return node.outputs["Vector"]

    def mix(self, factor, a, b):
        """Float lerp a -> b by factor."""
        node = self.node("ShaderNodeMix", {"Factor_Float": factor, "A_Float": a, "B_Float": b},
                         data_type="FLOAT")
        return Value(self, socket(node.outputs, "Result_Float"))

    # The formulas' maths (water_model.py), as Math nodes.
    def max(self, a, b):
        return self.math("MAXIMUM", a, b)

    def min(self, a, b):
        return self.math("MINIMUM", a, b)

    def clamp(self, x):
        return self.math("ADD", x, 0.0, clamp=True)

    def log(self, x):
        return self.math("LOGARITHM", x, math.e)

    def exp(self, x):
        return self.math("EXPONENT", x)

    def sqrt(self, x):
        return self.math("SQRT", x)

    def pow(self, a, b):
        return self.math("POWER", a, b)

    def abs(self, x):
        return self.math("ABSOLUTE", x)

    def less(self, a, b):
        return self.math("LESS_THAN", a, b)

    def greater(self, a, b):
        return self.math("GREATER_THAN", a, b)

    def cos(self, x):
        return self.math("COSINE", x)

    def sin(self, x):
        return self.math("SINE", x)
