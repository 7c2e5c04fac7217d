"""The Blender layer: it reads the scene, calls the core, and writes our own data.

    scene.py       reading: where oceans show, the camera, the time, the sun, the objects
    frame.py       one frame of one ocean: read -> build -> decide -> fields -> write
    mesh.py        writing our meshes
    companions.py  our objects beside an ocean: stand-ins, water body, shadow caster, probe
    settings.py    `obj.projgrid`
    state.py       what is kept between frames (one typed state per surface)
    handlers.py    the persistent handlers that run it all
"""
