"""Shader node trees built from code: the water node group and the default sky."""
