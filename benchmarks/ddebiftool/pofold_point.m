function [kf,Tf,pfbr,pfuncs,suc]=pofold_point(funcs,fine,ip,varargin)
%% fold of cycles as a regular solution of DDE-BIFTOOL's extended system (SetupPOfold).
% The null vector also carries a component in the drift c (nullparind) and must
% satisfy the linearised pinning condition v_z(0)=0 (extra_cond); otherwise the
% translation mode (v = e_z) would be a trivial null vector everywhere.
k=orbit_measures(fine.point,ip); [~,j]=min(k);
dim=size(fine.point(1).profile,1);
% the pinning z(0)=0 must be active (extra_condition) for the initial null vector
fine.method.point.extra_condition=1;
[pt,ok]=p_correc(funcs,fine.point(j),ip.c,[],fine.method.point);
if ok, fine.point(j)=pt; end
[pfuncs,pfbr,suc]=SetupPOfold(funcs,fine,j,'contpar',[ip.k,ip.c],...
    'nullparind',ip.c,'extra_cond',{@(p,pref)nullpin(p,dim)},...
    'sys_deri',funcs.sys_deri,'dir',[],varargin{:});
sol=pfuncs.get_comp(pfbr.point(1),'solution');
kf=sol.parameter(ip.k); Tf=sol.period;
end
function [r,J]=nullpin(p,dim)
r=p.profile(dim+1,1);
J=p_axpy(0,p,[]); J.profile(dim+1,1)=1;
end
